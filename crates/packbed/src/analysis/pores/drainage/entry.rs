//! The capillary entry pressure of a throat: the gas pressure, over the
//! surface tension, at which a meniscus passes the throat's constriction.
//!
//! - `inscribed` (Haines 1930): the meniscus of the largest circle the
//!   throat holds, `P_e = 2 γ cos θ / r_c` in 3D with `r_c` the constriction
//!   radius (the circle in the facet touching its three spheres), and
//!   `γ cos θ / r_c` in 2D (a cylindrical meniscus between two discs whose
//!   gap is `2 r_c`).
//! - `msp` (the default in 3D): the Mayer–Stowe–Princen balance of the
//!   facet's cross-section ([`super::msp`]), which counts the liquid
//!   left in the throat's three corners: the meniscus through a triangular
//!   throat is not a sphere, and the inscribed circle overstates the entry
//!   pressure of such throats (Mason & Morrow 1991; Joekar-Niasar et al.
//!   2010). In 2D the throat between two discs has no corners: `msp` is
//!   `inscribed` there.
// NaN-rejecting guards read `!(x > 0.0)`: true for NaN as well.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::super::network::Network;
use crate::bed::Bed;
use crate::config::EntryModel;
use crate::math::Real;

/// The entry curvature `P_e / γ` of throat `t` of `net` (`+∞` for a throat
/// closed to the gas); `cos` is the cosine of the contact angle.
pub fn entry_curvature<const D: usize>(
    bed: &Bed<D>,
    net: &Network<D>,
    t: usize,
    model: EntryModel,
    cos: Real,
) -> Real {
    let r = net.throats[t].constriction_radius;
    if !(r > 0.0) {
        return Real::INFINITY;
    }
    let inscribed = if D == 3 { 2.0 * cos / r } else { cos / r };
    match model {
        EntryModel::Inscribed => inscribed,
        EntryModel::Msp if D == 3 => {
            let (c, radii) = facet_circles(bed, net, t);
            // A facet MS-P cannot measure (degenerate, or closed by overlaps
            // deeper than it handles) keeps the inscribed circle's value.
            super::msp::msp_entry_radius_near(&c, &radii, cos.clamp(-1.0, 1.0).acos(), Some(r))
                .map_or(inscribed, |r_e| 1.0 / r_e)
        }
        EntryModel::Msp => inscribed,
    }
}

/// The facet of throat `t` as three circles in its own plane: the centres
/// in an orthonormal frame of the plane, and the radii (the facet passes
/// through the three centres, so each sphere cuts it in a great circle).
pub(super) fn facet_circles<const D: usize>(
    bed: &Bed<D>,
    net: &Network<D>,
    t: usize,
) -> ([[Real; 2]; 3], [Real; 3]) {
    let sites = super::facet_sites(net, t);
    let p: [[Real; 3]; 3] = std::array::from_fn(|k| {
        let q = sites[k].position(bed);
        std::array::from_fn(|a| q.get(a).copied().unwrap_or(0.0))
    });
    let radii = sites.map(|s| bed.radii[s.particle as usize]);
    let sub = |a: [Real; 3], b: [Real; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let dot = |a: [Real; 3], b: [Real; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let u = sub(p[1], p[0]);
    let lu = dot(u, u).sqrt();
    let e1 = u.map(|x| x / lu);
    let w = sub(p[2], p[0]);
    let along = dot(w, e1);
    let v = [
        w[0] - along * e1[0],
        w[1] - along * e1[1],
        w[2] - along * e1[2],
    ];
    let lv = dot(v, v).sqrt();
    let c = [[0.0, 0.0], [lu, 0.0], [along, lv]];
    (c, radii)
}
