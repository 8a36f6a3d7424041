//! The spring law of a bond and the rigid-body kinematics it needs
//! (`docs/reference/fragmentation.md`, "Spring law"): the motion of a body's material
//! point, the bond force, and the bond's stiffness blocks.
//!
//! A body has `D` translations and `R` rotations (2D: one angle; 3D: a rotation
//! vector), `M = D + R` unknowns in all, stored in fixed arrays of 6 so that
//! one code serves both dimensions.

use super::network::BondGeometry;
use crate::math::{Real, Vector};

/// Unknowns of one body in dimension `D`: translations plus rotations.
pub const fn body_dofs(d: usize) -> usize {
    if d == 2 {
        3
    } else {
        6
    }
}

/// A body's generalized vector (translation, then rotation), padded to 6.
pub type Dofs = [Real; 6];

/// The `D × M` matrix taking a body's unknowns to the motion of the material
/// point at `arm` from its reference point: `u + rotation × arm`.
pub fn motion<const D: usize>(arm: &Vector<D>) -> [[Real; 6]; 3] {
    let mut b = [[0.0; 6]; 3];
    for k in 0..D {
        b[k][k] = 1.0;
    }
    let a = arm.0;
    if D == 2 {
        // θ · (−a_y, a_x)
        b[0][2] = -a[1];
        b[1][2] = a[0];
    } else {
        // ω × a, columns 3..6 are ω_x, ω_y, ω_z
        b[0][4] = a[2];
        b[0][5] = -a[1];
        b[1][3] = -a[2];
        b[1][5] = a[0];
        b[2][3] = a[1];
        b[2][4] = -a[0];
    }
    b
}

/// `Bᵀ f`: the force `f` at `arm` as a generalized force (force, torque).
pub fn generalized<const D: usize>(arm: &Vector<D>, f: &Vector<D>) -> Dofs {
    let mut g = [0.0; 6];
    g[..D].copy_from_slice(&f.0);
    let (a, f) = (arm.0, f.0);
    if D == 2 {
        g[2] = a[0] * f[1] - a[1] * f[0];
    } else {
        g[3] = a[1] * f[2] - a[2] * f[1];
        g[4] = a[2] * f[0] - a[0] * f[2];
        g[5] = a[0] * f[1] - a[1] * f[0];
    }
    g
}

/// The motion of the material point at `arm` of a body moved by `u`.
pub fn point_motion<const D: usize>(arm: &Vector<D>, u: &[Real]) -> Vector<D> {
    let b = motion::<D>(arm);
    let m = body_dofs(D);
    let mut v = Vector::<D>::zero();
    for k in 0..D {
        v.0[k] = (0..m).map(|c| b[k][c] * u[c]).sum();
    }
    v
}

/// The spring stiffness `K = k_n n nᵀ + k_t (I − n nᵀ)` of a bond with normal `n`.
pub fn stiffness<const D: usize>(n: &Vector<D>, kn: Real, kt: Real) -> [[Real; 3]; 3] {
    let mut k = [[0.0; 3]; 3];
    for r in 0..D {
        for c in 0..D {
            let nn = n[r] * n[c];
            k[r][c] = (kn - kt) * nn + if r == c { kt } else { 0.0 };
        }
    }
    k
}

/// The symmetric square root `C` of a bond's `K` (`K = C C`), with `√k_n`
/// along the normal and `√k_t` across it: the low-rank factor of a bond's
/// stiffness that a breakage removes.
pub fn stiffness_root<const D: usize>(n: &Vector<D>, kn: Real, kt: Real) -> [[Real; 3]; 3] {
    stiffness::<D>(n, kn.sqrt(), kt.sqrt())
}

/// `K v` for a `D × D` block.
pub fn apply<const D: usize>(k: &[[Real; 3]; 3], v: &Vector<D>) -> Vector<D> {
    let mut out = Vector::<D>::zero();
    for r in 0..D {
        out.0[r] = (0..D).map(|c| k[r][c] * v[c]).sum();
    }
    out
}

/// The force bond `g` exerts on body i when the bodies move by `ui` and `uj`
/// (`uj` is ignored for a wall): `K (d_j(p) − d_i(p))`.
pub fn bond_force<const D: usize>(
    g: &BondGeometry<D>,
    k: &[[Real; 3]; 3],
    ui: &[Real],
    uj: Option<&[Real]>,
) -> Vector<D> {
    let di = point_motion::<D>(&g.arm_i, ui);
    let dj = match uj {
        Some(uj) => point_motion::<D>(&g.arm_j, uj),
        None => Vector::zero(),
    };
    apply::<D>(k, &(dj - di))
}

/// The stiffness blocks of a bond: `(K_ii, K_ij, K_jj)` of `M × M` with
/// `K_ii = B_iᵀ K B_i`, `K_ij = −B_iᵀ K B_j`, `K_jj = B_jᵀ K B_j`.
pub fn blocks<const D: usize>(g: &BondGeometry<D>, k: &[[Real; 3]; 3]) -> [[[Real; 6]; 6]; 3] {
    let m = body_dofs(D);
    let bi = motion::<D>(&g.arm_i);
    let bj = motion::<D>(&g.arm_j);
    // K B for both ends.
    let mut kbi = [[0.0; 6]; 3];
    let mut kbj = [[0.0; 6]; 3];
    for r in 0..D {
        for c in 0..m {
            for s in 0..D {
                kbi[r][c] += k[r][s] * bi[s][c];
                kbj[r][c] += k[r][s] * bj[s][c];
            }
        }
    }
    let mut out = [[[0.0; 6]; 6]; 3];
    for a in 0..m {
        for c in 0..m {
            let (mut ii, mut ij, mut jj) = (0.0, 0.0, 0.0);
            for r in 0..D {
                ii += bi[r][a] * kbi[r][c];
                ij -= bi[r][a] * kbj[r][c];
                jj += bj[r][a] * kbj[r][c];
            }
            out[0][a][c] = ii;
            out[1][a][c] = ij;
            out[2][a][c] = jj;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::math::v3::cross as cross3;

    #[test]
    fn motion_is_translation_plus_rotation_cross_arm() {
        let arm = Vector([0.3, -1.2, 2.0]);
        let u = [0.1, 0.2, -0.3, 0.7, -0.4, 0.25];
        let got = point_motion::<3>(&arm, &u);
        let w = cross3([u[3], u[4], u[5]], arm.0);
        for k in 0..3 {
            assert!((got[k] - (u[k] + w[k])).abs() < 1e-15);
        }
        // 2D: θ ẑ × a = θ (−a_y, a_x).
        let got = point_motion::<2>(&Vector([0.5, 2.0]), &[1.0, -1.0, 0.1, 0.0, 0.0, 0.0]);
        assert!((got[0] - (1.0 - 0.2)).abs() < 1e-15 && (got[1] - (-1.0 + 0.05)).abs() < 1e-15);
    }

    #[test]
    fn generalized_force_is_the_transpose_of_the_motion() {
        // Virtual work: f · (B u) = (Bᵀ f) · u for every u.
        let arm = Vector([0.3, -1.2, 2.0]);
        let f = Vector([1.5, -0.5, 0.25]);
        let g = generalized::<3>(&arm, &f);
        let u = [0.1, 0.2, -0.3, 0.7, -0.4, 0.25];
        let lhs = f.dot(&point_motion::<3>(&arm, &u));
        let rhs: Real = (0..6).map(|c| g[c] * u[c]).sum();
        assert!((lhs - rhs).abs() < 1e-14);
    }

    #[test]
    fn root_squares_to_the_stiffness() {
        let n = Vector([0.6, 0.0, 0.8]);
        let (k, c) = (
            stiffness::<3>(&n, 2.0, 0.5),
            stiffness_root::<3>(&n, 2.0, 0.5),
        );
        for r in 0..3 {
            for s in 0..3 {
                let cc: Real = (0..3).map(|t| c[r][t] * c[t][s]).sum();
                assert!((cc - k[r][s]).abs() < 1e-14);
            }
        }
    }
}
