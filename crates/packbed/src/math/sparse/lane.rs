//! The numbers a multigrid cycle's vectors hold.
//!
//! The cycle is a preconditioner: conjugate gradients need `M⁻¹ r` only
//! near `A⁻¹ r` (a V-cycle is off by a factor of a few anyway), while its
//! residuals, its products with `A` and its answer stay in double
//! precision, so the solution's accuracy does not depend on the cycle's.
//! In single precision a sweep streams half the bytes of its vectors, and
//! the sweeps are bound by memory, not arithmetic.

use crate::math::Real;
use std::ops::{Add, AddAssign, Mul, Sub, SubAssign};

/// `f32` in the cycle, `f64` where it meets conjugate gradients.
pub trait Lane:
    Copy
    + Default
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + AddAssign
    + SubAssign
{
    /// The nearest value of this type.
    fn of(v: Real) -> Self;
    /// The value in double precision (exact).
    fn real(self) -> Real;
    /// The nearest value of this type to another lane's.
    fn from_lane<B: Lane>(b: B) -> Self {
        Self::of(b.real())
    }
}

impl Lane for f32 {
    #[inline(always)]
    fn of(v: Real) -> f32 {
        v as f32
    }
    #[inline(always)]
    fn real(self) -> Real {
        Real::from(self)
    }
}

impl Lane for f64 {
    #[inline(always)]
    fn of(v: Real) -> f64 {
        v
    }
    #[inline(always)]
    fn real(self) -> Real {
        self
    }
}
