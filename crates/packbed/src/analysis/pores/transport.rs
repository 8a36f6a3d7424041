//! What else flows through the pore network, solved by the flow's solver:
//! the formation factor (conduction or diffusion through the liquid-filled
//! pore space, what washing a cake depends on), the hydraulic tortuosity of
//! the solved flow, and the relative permeability of each phase of a partly
//! drained bed.
//!
//! - Formation factor `F = σ_liquid / σ_bed`: the same network with each
//!   throat's diffusive conductance `A_f / L` (fluid area of the facet over
//!   the distance between the power centres), closed where the flow's
//!   throat is closed; `F` is 1 over the slab's effective conductivity
//!   along z. Archie's exponent `m = −ln F / ln φ` with the network's
//!   porosity, and the electrical tortuosity `F φ`.
//! - Hydraulic tortuosity `τ = Σ |q| L / Σ q Δz` over the slab's throats of
//!   the flow along z: the mean length fluid travels per unit of height
//!   (the network form of Duda, Koza & Matyka's ⟨|u|⟩ / ⟨u_z⟩; a fluid
//!   volume crossing a throat moves its length `L` and rises `Δz`).

use super::flow::{self, Flow, FlowError};
use super::network::{Network, ThroatShape};
use crate::math::{Real, Vector};
use rayon::prelude::*;
use serde::Serialize;

/// `transport.*` keys of `summary.json`.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct TransportSummary {
    /// Formation factor along z: the liquid's conductivity over the
    /// liquid-filled bed's.
    pub formation_factor: Option<Real>,
    /// Archie's cementation exponent `m` with the network's porosity.
    pub archie_exponent: Option<Real>,
    /// `F φ`: the electrical (diffusive) tortuosity.
    pub electrical_tortuosity: Option<Real>,
    /// Hydraulic tortuosity of the flow along z.
    pub hydraulic_tortuosity: Option<Real>,
    /// How far to trust `formation_factor` (and `archie_exponent`,
    /// `electrical_tortuosity`): [`FORMATION_FACTOR_MODEL`].
    pub formation_factor_model: &'static str,
    /// Why a figure above is null, when one is.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
}

/// What the formation factor is: each throat conducts through its facet's
/// fluid area over the whole distance between its cells' centres, the pore
/// bodies left out, which overstates the resistance: on 4,000 random equal
/// spheres `F` is 39 % above a converged voxel solve of the same bed
/// (docs/deliquoring-validation.md, section 1.4).
pub const FORMATION_FACTOR_MODEL: &str =
    "throat conductances A_f/L, pore bodies left out: an upper bound (39 % above a voxel solve on random equal spheres)";

/// Each throat's diffusive conductance `A_f / L` (0 for a throat of no
/// length: its pores are merged).
pub fn diffusive_conductances(shapes: &[ThroatShape]) -> Vec<Real> {
    shapes
        .par_iter()
        .map(|s| {
            let g = s.fluid_area / s.length;
            if g.is_finite() && g > 0.0 {
                g
            } else {
                0.0
            }
        })
        .collect()
}

/// The formation factor and tortuosities of the slab, from the solved
/// `flow` (whose axes are `axes`), the throats `merge`d by the flow, their
/// diffusive conductances and the slab's network porosity.
#[allow(clippy::too_many_arguments)]
pub fn transport<const D: usize>(
    net: &Network<D>,
    merge: &[bool],
    diffusive: &[Real],
    flow: &Flow,
    axes: &[usize],
    size: &Vector<D>,
    slab: (Real, Real),
    porosity: Option<Real>,
) -> Result<TransportSummary, FlowError> {
    let z = D - 1;
    let mut out = TransportSummary {
        formation_factor_model: FORMATION_FACTOR_MODEL,
        ..TransportSummary::default()
    };
    let open: Vec<Real> = diffusive
        .iter()
        .zip(&flow.conductance)
        .map(|(&d, &g)| if g > 0.0 { d } else { 0.0 })
        .collect();
    let (f, _) = flow::solve_z(net, merge, &open, size, slab)?;
    match f.k {
        Some(k) if k > 0.0 => {
            let ff = 1.0 / k;
            out.formation_factor = Some(ff);
            if let Some(phi) = porosity.filter(|&p| p > 0.0 && p < 1.0) {
                out.archie_exponent = Some(-ff.ln() / phi.ln());
                out.electrical_tortuosity = Some(ff * phi);
            }
        }
        _ => out.note = Some("no conducting path crosses the slab along z".into()),
    }
    if let Some(k) = axes.iter().position(|&a| a == z) {
        out.hydraulic_tortuosity = hydraulic_tortuosity(net, &flow.throat_flux[k], size, slab);
    }
    Ok(out)
}

/// `Σ |q| L / Σ q Δz` over the throats between two pores of the slab.
fn hydraulic_tortuosity<const D: usize>(
    net: &Network<D>,
    flux: &[Real],
    size: &Vector<D>,
    slab: (Real, Real),
) -> Option<Real> {
    let z = D - 1;
    let inside = |p: u32| {
        let h = net.pores[p as usize].centre[z];
        h >= slab.0 && h <= slab.1
    };
    let (mut travelled, mut risen) = (0.0, 0.0);
    for (th, &q) in net.throats.iter().zip(flux) {
        if q == 0.0 || !inside(th.pores[0]) || !inside(th.pores[1]) {
            continue;
        }
        let a = &net.pores[th.pores[0] as usize].centre;
        let b = &net.pores[th.pores[1] as usize].centre;
        let mut l2 = 0.0;
        for k in 0..D {
            let shift = if k < z {
                Real::from(th.shift[k]) * size[k]
            } else {
                0.0
            };
            l2 += (b[k] + shift - a[k]).powi(2);
        }
        travelled += q.abs() * l2.sqrt();
        risen += q * (b[z] - a[z]);
    }
    let tau = travelled / risen.abs();
    (tau.is_finite() && tau >= 1.0 - 1e-9).then_some(tau)
}
