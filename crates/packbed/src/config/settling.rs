//! `[settling]`: how a dropped particle comes to rest. Without the table a
//! particle rolls, frictionless and without cohesion, until its supports hold
//! it (three in 3D, two in 2D, or the floor); each key moves the rule toward
//! looser beds:
//!
//! - `contacts = k` (1, 2 or 3): it stops at the k-th contact it touches at
//!   once (1 is ballistic deposition, hit-and-stick; 2 the restructuring to
//!   two contacts of Jullien & Meakin; 3, in 3D, stops on three supports even
//!   where it would roll off them). A particle at rest earlier stays.
//! - `sticking = p` in [0, 1]: at each new contact it sticks there with
//!   probability p, else rolls on (p = 1 is hit-and-stick, p = 0 today's rule).
//! - `friction_angle = α` in degrees, [0, 90): it stops where the downhill
//!   slope of its path falls below α (on one support the tilt of the contact
//!   normal from the vertical, in a groove the groove's slope), so that a
//!   slope steeper than α never holds a particle and a heap stands near it.
//!
//! Side walls are no contacts for `contacts` and `sticking`: they guide a
//! particle, the floor and the particles hold it.

use crate::error::{Error, Result};
use crate::math::Real;
use serde::{Deserialize, Serialize};

/// `[settling]` as written.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SettlingConfig {
    /// Stop at the k-th simultaneous contact (1, 2 or 3).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contacts: Option<u8>,
    /// Probability of sticking at each new contact.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sticking: Option<Real>,
    /// Friction angle in degrees.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction_angle: Option<Real>,
}

impl SettlingConfig {
    /// True if nothing is set: today's rule.
    pub fn is_default(&self) -> bool {
        *self == SettlingConfig::default()
    }

    /// The rule, checked.
    pub fn resolve(&self) -> Result<Settling> {
        let contacts = match self.contacts {
            None => None,
            Some(k @ 1..=3) => Some(k),
            Some(k) => {
                return Err(Error::config(format!(
                    "settling.contacts must be 1, 2 or 3, got {k}"
                )))
            }
        };
        let sticking = match self.sticking {
            None => 0.0,
            Some(p) if (0.0..=1.0).contains(&p) => p,
            Some(p) => {
                return Err(Error::config(format!(
                    "settling.sticking must be a probability in [0, 1], got {p}"
                )))
            }
        };
        let slope = match self.friction_angle {
            None => None,
            Some(a) if (0.0..90.0).contains(&a) => {
                // A zero angle stops nothing: the frictionless rule.
                (a > 0.0).then(|| a.to_radians().sin())
            }
            Some(a) => {
                return Err(Error::config(format!(
                    "settling.friction_angle must be in [0, 90) degrees, got {a}"
                )))
            }
        };
        Ok(Settling {
            contacts,
            sticking,
            slope,
        })
    }
}

/// The settling rule of a run, checked.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Settling {
    /// Stop at this many simultaneous contacts (side walls not counted).
    pub contacts: Option<u8>,
    /// Probability of sticking at each new contact (0: never).
    pub sticking: Real,
    /// Sine of the friction angle: a path less steep than this stops.
    pub slope: Option<Real>,
}

impl Settling {
    /// True for today's rule (roll until at rest), which settles bit for bit
    /// as before the rules existed.
    pub fn is_rolling(&self) -> bool {
        *self == Settling::default()
    }

    /// The friction angle in degrees, if any.
    pub fn friction_angle(&self) -> Option<Real> {
        self.slope.map(|s| s.asin().to_degrees())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn resolve(text: &str) -> Result<Settling> {
        toml::from_str::<SettlingConfig>(text)
            .map_err(|e| Error::config(e.to_string()))?
            .resolve()
    }

    #[test]
    fn nothing_set_is_the_rolling_rule() {
        let s = resolve("").unwrap();
        assert!(s.is_rolling());
        // A zero friction angle and a zero sticking probability stop nothing.
        assert!(resolve("friction_angle = 0\nsticking = 0")
            .unwrap()
            .is_rolling());
    }

    #[test]
    fn out_of_range_values_are_refused_with_the_key() {
        for (text, key) in [
            ("contacts = 0", "settling.contacts"),
            ("contacts = 4", "settling.contacts"),
            ("sticking = 1.5", "settling.sticking"),
            ("sticking = -0.1", "settling.sticking"),
            ("sticking = nan", "settling.sticking"),
            ("friction_angle = 90", "settling.friction_angle"),
            ("friction_angle = -1", "settling.friction_angle"),
            ("friction_angle = inf", "settling.friction_angle"),
        ] {
            let e = resolve(text).unwrap_err().to_string();
            assert!(e.contains(key), "{text}: {e}");
            assert!(!e.contains('\n'), "{text}: {e}");
        }
    }

    #[test]
    fn the_friction_angle_is_kept_as_its_sine() {
        let s = resolve("friction_angle = 30").unwrap();
        assert!((s.slope.unwrap() - 0.5).abs() < 1e-15);
        assert!((s.friction_angle().unwrap() - 30.0).abs() < 1e-12);
    }
}
