//! Real type, fixed-size vectors and the dimension of space.
//!
//! Every geometric routine in packbed is generic over `const D: usize` (2 or 3) and
//! works on [`Vector<D>`]. This module is the only place that names a concrete
//! dimension; the last axis is always vertical ("up"). The least-squares
//! routines of the force balances live in `lsq.rs`, the rotations of turning
//! bodies in `rotation.rs`, the standard normal distribution of the size
//! distributions in `normal.rs`.

use std::ops::{Add, AddAssign, Div, Index, IndexMut, Mul, Neg, Sub, SubAssign};

/// The real number type of all geometry.
pub type Real = f64;

/// Smallest and largest lengths (radii, box extents, table sizes) packbed
/// works with. The geometry squares lengths (and multiplies squares), so far
/// outside this range they leave the normal range of floating point: radii of
/// 1e-100 gave beds with overlapping particles, and 1e160 made the run spin
/// for ever. Any unit system fits inside (nanometres in metres are 1e-9).
pub const LENGTH_RANGE: (Real, Real) = (1e-30, 1e30);

/// A point or direction in `D`-dimensional space; the last component is height.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vector<const D: usize>(pub [Real; D]);

impl<const D: usize> Default for Vector<D> {
    fn default() -> Self {
        Self::zero()
    }
}

impl<const D: usize> Vector<D> {
    /// Index of the vertical axis.
    pub const UP: usize = D - 1;

    /// The zero vector.
    #[inline]
    pub const fn zero() -> Self {
        Vector([0.0; D])
    }

    /// The unit vector pointing up (against gravity).
    #[inline]
    pub(crate) fn up() -> Self {
        Self::axis(D - 1)
    }

    /// The unit vector along axis `k`.
    #[inline]
    pub(crate) fn axis(k: usize) -> Self {
        let mut v = Self::zero();
        v.0[k] = 1.0;
        v
    }

    /// Height (the vertical component).
    #[inline]
    pub(crate) fn height(&self) -> Real {
        self.0[D - 1]
    }

    /// Scalar product.
    #[inline]
    pub(crate) fn dot(&self, o: &Self) -> Real {
        let mut s = 0.0;
        for k in 0..D {
            s += self.0[k] * o.0[k];
        }
        s
    }

    /// Squared Euclidean length.
    #[inline]
    pub(crate) fn norm2(&self) -> Real {
        self.dot(self)
    }

    /// Euclidean length.
    #[inline]
    pub fn norm(&self) -> Real {
        self.norm2().sqrt()
    }

    /// This vector scaled to unit length, or `None` for a (near) zero vector.
    #[inline]
    pub(crate) fn normalized(&self) -> Option<Self> {
        let n = self.norm();
        if n > 0.0 && n.is_finite() {
            Some(*self / n)
        } else {
            None
        }
    }

    /// The horizontal part (vertical component set to zero).
    #[inline]
    pub(crate) fn horizontal(&self) -> Self {
        let mut v = *self;
        v.0[D - 1] = 0.0;
        v
    }

    /// True when every component is finite.
    pub(crate) fn is_finite(&self) -> bool {
        self.0.iter().all(|c| c.is_finite())
    }
}

impl<const D: usize> Index<usize> for Vector<D> {
    type Output = Real;
    #[inline]
    fn index(&self, k: usize) -> &Real {
        &self.0[k]
    }
}

impl<const D: usize> IndexMut<usize> for Vector<D> {
    #[inline]
    fn index_mut(&mut self, k: usize) -> &mut Real {
        &mut self.0[k]
    }
}

impl<const D: usize> Add for Vector<D> {
    type Output = Self;
    #[inline]
    fn add(mut self, o: Self) -> Self {
        for k in 0..D {
            self.0[k] += o.0[k];
        }
        self
    }
}

impl<const D: usize> AddAssign for Vector<D> {
    #[inline]
    fn add_assign(&mut self, o: Self) {
        for k in 0..D {
            self.0[k] += o.0[k];
        }
    }
}

impl<const D: usize> Sub for Vector<D> {
    type Output = Self;
    #[inline]
    fn sub(mut self, o: Self) -> Self {
        for k in 0..D {
            self.0[k] -= o.0[k];
        }
        self
    }
}

impl<const D: usize> SubAssign for Vector<D> {
    #[inline]
    fn sub_assign(&mut self, o: Self) {
        for k in 0..D {
            self.0[k] -= o.0[k];
        }
    }
}

impl<const D: usize> Mul<Real> for Vector<D> {
    type Output = Self;
    #[inline]
    fn mul(mut self, s: Real) -> Self {
        for k in 0..D {
            self.0[k] *= s;
        }
        self
    }
}

impl<const D: usize> Div<Real> for Vector<D> {
    type Output = Self;
    #[inline]
    fn div(self, s: Real) -> Self {
        self * (1.0 / s)
    }
}

impl<const D: usize> Neg for Vector<D> {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        self * -1.0
    }
}

/// The least and the greatest coordinate on each axis of `points`
/// (infinite, lo above hi, for no points).
pub fn bounds<const D: usize>(points: &[[f64; D]]) -> ([f64; D], [f64; D]) {
    let mut lo = [f64::INFINITY; D];
    let mut hi = [f64::NEG_INFINITY; D];
    for p in points {
        for k in 0..D {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (lo, hi)
}

/// Volume of a `D`-ball of radius `r` (area of a disc in 2D).
pub fn ball_volume<const D: usize>(r: Real) -> Real {
    match D {
        1 => 2.0 * r,
        2 => std::f64::consts::PI * r * r,
        3 => 4.0 / 3.0 * std::f64::consts::PI * r * r * r,
        _ => unreachable!("packbed works in 2 or 3 dimensions"),
    }
}

/// A length for a person to read (the screen, species descriptions): at most six significant digits (but the whole
/// integer part), trailing zeros dropped, so that a box of 1485.1720000000003
/// reads 1485.17 (`summary.json` keeps every digit).
pub fn display_length(x: Real) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let magnitude = x.abs().log10().floor() as i32;
    let trim = |t: String| -> String {
        if t.contains('.') {
            t.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            t
        }
    };
    if !(-4..15).contains(&magnitude) {
        let t = format!("{x:.5e}");
        let (mantissa, exponent) = t.split_once('e').unwrap_or((&t, "0"));
        return format!("{}e{exponent}", trim(mantissa.to_string()));
    }
    let decimals = (5 - magnitude).max(0) as usize;
    trim(format!("{x:.decimals$}"))
}

/// A generalised vector of a rigid body: translation in slots `0..D`, rotation
/// (times a radius of gyration) in slot 2 (2D) or slots 3–5 (3D).
pub type Gen = Vector<6>;

pub(crate) mod hilbert;
mod lsq;
pub(crate) mod normal;
pub mod predicates;
mod rotation;
pub mod sparse;
pub mod v3;

pub use lsq::{nnls, nnls_gen, nnls_qr, solve_pivoted, MAX_GEN_COLUMNS};
pub use rotation::{moment, rotate};
