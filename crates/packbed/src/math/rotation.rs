//! Rotations in the plane and in space, for bodies that turn as they settle.

use super::{Real, Vector};

/// `a` turned by `w`: by the angle `w[0]` in 2D, by the rotation vector `w`
/// (its length the angle, Rodrigues' formula) in 3D.
pub fn rotate<const D: usize>(a: Vector<D>, w: [Real; 3]) -> Vector<D> {
    let mut out = a;
    if D == 2 {
        let (sn, cs) = w[0].sin_cos();
        out[0] = a[0] * cs - a[1] * sn;
        out[1] = a[0] * sn + a[1] * cs;
    } else {
        let t = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
        if t > 0.0 {
            let k = [w[0] / t, w[1] / t, w[2] / t];
            let (sn, cs) = t.sin_cos();
            let kxa = [
                k[1] * a[2] - k[2] * a[1],
                k[2] * a[0] - k[0] * a[2],
                k[0] * a[1] - k[1] * a[0],
            ];
            let kda = k[0] * a[0] + k[1] * a[1] + k[2] * a[2];
            for i in 0..3 {
                out[i] = a[i] * cs + kxa[i] * sn + k[i] * kda * (1.0 - cs);
            }
        }
    }
    out
}

/// The moment `l × n` of a force `n` applied at lever `l`: a scalar in 2D (the
/// first entry, the others 0), a vector in 3D.
#[inline]
pub fn moment<const D: usize>(l: &Vector<D>, n: &Vector<D>) -> [Real; 3] {
    if D == 2 {
        [l[0] * n[1] - l[1] * n[0], 0.0, 0.0]
    } else {
        [
            l[1] * n[2] - l[2] * n[1],
            l[2] * n[0] - l[0] * n[2],
            l[0] * n[1] - l[1] * n[0],
        ]
    }
}
