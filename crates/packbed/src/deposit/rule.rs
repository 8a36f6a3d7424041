//! What the settling rules ([`Settling`]) share between spheres and chains:
//! which contacts hold a body, and the draws of the sticking rule.

use super::obstacle::{is_floor, Obstacle};
use crate::config::Settling;
use crate::math::{Real, Vector};
use rand::{RngExt, SeedableRng};
use rand_xoshiro::SplitMix64;

/// Least height of a contact normal (from the obstacle to the body's centre,
/// a unit vector) that holds: a touch at a particle's equator, or under it,
/// holds nothing up.
const HOLDING: Real = 1e-4;

/// True for a contact the `contacts` rule counts: the floor or a particle,
/// whichever side it is touched on (side walls only guide).
#[inline]
pub(crate) fn counts<const D: usize>(o: &Obstacle<D>) -> bool {
    is_floor(o.key) || o.surface.is_ball()
}

/// True for a contact that holds a body up, where it may stick: the floor, or a particle touched
/// above its equator (normal pointing up) by the bead at `at`. Side walls
/// only guide.
#[inline]
pub(crate) fn holds<const D: usize>(o: &Obstacle<D>, at: &Vector<D>) -> bool {
    is_floor(o.key) || (o.surface.is_ball() && o.surface.normal_at(at)[D - 1] > HOLDING)
}

/// The draws of the sticking rule: a generator of their own, seeded by the
/// entry point (itself drawn from the run's generator), so that the rule takes
/// nothing from the run's draws and a speculative settling draws what the
/// one-at-a-time settling draws.
pub(crate) struct Sticks {
    p: Real,
    draws: Option<SplitMix64>,
}

impl Sticks {
    /// The draws of a body of bead radius `r` entering at the horizontal
    /// coordinates `entry`.
    pub(crate) fn new(rule: &Settling, r: Real, entry: &[Real]) -> Self {
        let p = rule.sticking_at(r);
        let draws = (p > 0.0 && p < 1.0).then(|| {
            let seed = entry.iter().fold(0x5ee1_57c4_u64, |h, x| {
                (h ^ x.to_bits()).wrapping_mul(0x9e37_79b9_7f4a_7c15)
            });
            SplitMix64::seed_from_u64(seed)
        });
        Sticks { p, draws }
    }

    /// Whether the particle sticks at the contacts it just made.
    pub(crate) fn stick(&mut self) -> bool {
        match &mut self.draws {
            _ if self.p >= 1.0 => true,
            _ if self.p <= 0.0 => false,
            Some(d) => d.random::<Real>() < self.p,
            None => false,
        }
    }
}
