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
//! - `cohesion_diameter = d_c` (a length), with `cohesion_exponent = n`
//!   (default 2): the sticking probability of a particle of diameter d is
//!   `p = 1 / (1 + (d / d_c)ⁿ)`, so fines stick and coarse particles roll.
//!   The law is the Bond number's: van der Waals adhesion between spheres
//!   grows as d, their weight as d³, so `Bo = F / (m g) ∝ d⁻²`. With one
//!   adhesion force for every contact, `p = Bo / (Bo + Bo_c)` (n = 2), `Bo_c`
//!   the Bond number at which half the contacts stick, at diameter d_c. Rough
//!   contacts spread the adhesion force: if it is log-logistic about its
//!   mean, with shape β, `p` keeps this form with n = 2β, so a smaller n is
//!   a wider spread. Fitted to the porosity of deposited sediments against
//!   size (Wu & Wang 2006): d_c = 5.2 µm, n = 0.70 (docs/settling.md).
//!   Instead of `sticking`, not with it.
//! - `friction_angle = α` in degrees, [0, 90): it stops where the downhill
//!   slope of its path falls below α (on one support the tilt of the contact
//!   normal from the vertical, in a groove the groove's slope), so that a
//!   slope steeper than α never holds a particle. Held where it lands, a
//!   particle on a heap's flank stays at any particle's top: a spire. With
//!   `restitution`, a particle with energy left slides over such spots,
//!   losing µ = tan α (or `sliding_friction`) per horizontal travel, and
//!   stops where its energy is spent on a stretch less steep than α.
//! - `restitution = e` in [0, 1), with `drop_height = h` (a length; default
//!   the particle's diameter): momentum. The particle lands with the kinetic
//!   energy of a fall from h, gains what it descends, keeps at each impact the
//!   tangential part of its energy and e² of the normal part, and leaves a
//!   pocket over its lowest open rim when its energy is above the rim. This
//!   moves the rule toward denser beds. `sliding_friction = µ` (default 0)
//!   takes µ times each move's horizontal travel from the energy.
//!   `climb_over = true`: a climb out of a pocket that meets another
//!   particle rolls on over it (default: that way out is closed). Spheres
//!   and discs only; not with `contacts`.
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
    /// The diameter at which half the contacts stick (size-dependent
    /// cohesion), in the config's length units.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cohesion_diameter: Option<Real>,
    /// The exponent n of the cohesion law `1 / (1 + (d / d_c)ⁿ)` (default 2;
    /// needs `cohesion_diameter`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cohesion_exponent: Option<Real>,
    /// The restitution coefficient of an impact (turns momentum on).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub restitution: Option<Real>,
    /// The height of the free fall before the first impact, in the config's
    /// length units (needs `restitution`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub drop_height: Option<Real>,
    /// The momentum rule's sliding friction coefficient (needs `restitution`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sliding_friction: Option<Real>,
    /// With momentum: a climb out of a pocket that meets another particle
    /// rolls on over it instead of ending there (needs `restitution`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub climb_over: Option<bool>,
}

impl SettlingConfig {
    /// True if nothing is set: today's rule.
    pub(crate) fn is_default(&self) -> bool {
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
        let cohesion = match self.cohesion_diameter {
            None => None,
            Some(_) if self.sticking.is_some() => {
                return Err(Error::config(
                    "settling: give either `sticking` (one probability) or `cohesion_diameter` (a probability by size), not both",
                ))
            }
            Some(d) if d.is_finite() && d > 0.0 => Some(Cohesion {
                diameter: d,
                exponent: self.cohesion_exponent()?,
            }),
            Some(d) => {
                return Err(Error::config(format!(
                    "settling.cohesion_diameter must be a positive length, got {d}"
                )))
            }
        };
        if cohesion.is_none() && self.cohesion_exponent.is_some() {
            return Err(Error::config(
                "settling.cohesion_exponent shapes the cohesion law: give `cohesion_diameter` too",
            ));
        }
        let mut momentum = self.momentum()?;
        if momentum.is_some() && contacts.is_some() {
            return Err(Error::config(
                "settling: `restitution` (momentum) acts at rest and on the way down; it does not combine with `contacts`",
            ));
        }
        if let (Some(m), Some(s), None) = (momentum.as_mut(), slope, self.sliding_friction) {
            // Coulomb's law with one coefficient: a particle that slides
            // loses what the static friction of the angle would hold,
            // µ = tan α.
            m.sliding_friction = s / (1.0 - s * s).sqrt();
        }
        Ok(Settling {
            contacts,
            sticking,
            slope,
            cohesion,
            momentum,
        })
    }

    /// `cohesion_exponent`, checked.
    fn cohesion_exponent(&self) -> Result<Real> {
        match self.cohesion_exponent {
            None => Ok(2.0),
            // Beyond 50 the law is a step at d_c to double precision.
            Some(n) if n.is_finite() && n > 0.0 && n <= 50.0 => Ok(n),
            Some(n) => Err(Error::config(format!(
                "settling.cohesion_exponent must be in (0, 50], got {n}"
            ))),
        }
    }

    /// `restitution` and `drop_height`, checked.
    fn momentum(&self) -> Result<Option<Momentum>> {
        let drop_height =
            match self.drop_height {
                None => None,
                Some(_) if self.restitution.is_none() => return Err(Error::config(
                    "settling.drop_height is the fall of the momentum rule: give `restitution` too",
                )),
                Some(h) if h.is_finite() && h >= 0.0 => Some(h),
                Some(h) => {
                    return Err(Error::config(format!(
                        "settling.drop_height must be a length >= 0, got {h}"
                    )))
                }
            };
        let sliding_friction = match self.sliding_friction {
            None => 0.0,
            Some(_) if self.restitution.is_none() => {
                return Err(Error::config(
                    "settling.sliding_friction is the momentum rule's: give `restitution` too",
                ))
            }
            Some(mu) if mu.is_finite() && mu >= 0.0 => mu,
            Some(mu) => {
                return Err(Error::config(format!(
                    "settling.sliding_friction must be a coefficient >= 0, got {mu}"
                )))
            }
        };
        if self.climb_over.is_some() && self.restitution.is_none() {
            return Err(Error::config(
                "settling.climb_over is the momentum rule's: give `restitution` too",
            ));
        }
        match self.restitution {
            None => Ok(None),
            Some(e) if (0.0..1.0).contains(&e) => Ok(Some(Momentum {
                restitution: e,
                drop_height,
                sliding_friction,
                climb_over: self.climb_over.unwrap_or(false),
            })),
            Some(e) => Err(Error::config(format!(
                "settling.restitution must be in [0, 1), got {e}"
            ))),
        }
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
    /// The cohesion law, when the sticking probability depends on size
    /// (then `sticking` is 0).
    pub cohesion: Option<Cohesion>,
    /// Momentum: the energy a particle carries (`None`: quasi-static).
    pub momentum: Option<Momentum>,
}

/// The size-dependent cohesion law `p = 1 / (1 + (d / d_c)ⁿ)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cohesion {
    /// d_c: the diameter at which half the contacts stick.
    pub diameter: Real,
    /// n: how sharply sticking gives way to rolling as d passes d_c.
    pub exponent: Real,
}

/// The momentum rule's parameters.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Momentum {
    /// Restitution coefficient of an impact, in [0, 1): the share of the
    /// normal velocity kept.
    pub restitution: Real,
    /// The free fall before the first impact (`None`: the particle's diameter).
    pub drop_height: Option<Real>,
    /// Coulomb's coefficient µ of the sliding on supports: a move loses µ
    /// times its horizontal travel (a block sliding down a plane loses
    /// `µ N ds = µ m g dx`).
    pub sliding_friction: Real,
    /// A climb out of a pocket that meets another particle rolls on over it
    /// (on the groove of the blocker and the supports the way on keeps)
    /// instead of ending there.
    pub climb_over: bool,
}

impl Settling {
    /// True for today's rule (roll until at rest), which settles bit for bit
    /// as before the rules existed.
    pub(crate) fn is_rolling(&self) -> bool {
        *self == Settling::default()
    }

    /// The probability that a particle of radius `r` sticks at a new
    /// contact: `sticking`, or by the cohesion law `1 / (1 + (2r / d_c)ⁿ)`.
    pub(crate) fn sticking_at(&self, r: Real) -> Real {
        match self.cohesion {
            // n = 2 squares exactly, as the law did before it had an exponent.
            Some(c) if c.exponent == 2.0 => 1.0 / (1.0 + (2.0 * r / c.diameter).powi(2)),
            Some(c) => 1.0 / (1.0 + (2.0 * r / c.diameter).powf(c.exponent)),
            None => self.sticking,
        }
    }

    /// True if particles may stick at a new contact.
    pub fn sticks(&self) -> bool {
        self.sticking > 0.0 || self.cohesion.is_some()
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
            ("cohesion_diameter = 0", "settling.cohesion_diameter"),
            ("cohesion_diameter = -2", "settling.cohesion_diameter"),
            ("cohesion_diameter = 2\nsticking = 0.1", "not both"),
            ("cohesion_exponent = 1", "settling.cohesion_exponent"),
            (
                "cohesion_diameter = 2\ncohesion_exponent = 0",
                "settling.cohesion_exponent",
            ),
            (
                "cohesion_diameter = 2\ncohesion_exponent = nan",
                "settling.cohesion_exponent",
            ),
            (
                "cohesion_diameter = 2\ncohesion_exponent = 51",
                "settling.cohesion_exponent",
            ),
            ("restitution = 1", "settling.restitution"),
            ("restitution = -0.1", "settling.restitution"),
            ("restitution = nan", "settling.restitution"),
            ("drop_height = 3", "settling.drop_height"),
            (
                "restitution = 0.5\ndrop_height = -1",
                "settling.drop_height",
            ),
            (
                "restitution = 0.5\ndrop_height = inf",
                "settling.drop_height",
            ),
            ("restitution = 0.5\ncontacts = 3", "does not combine"),
            ("sliding_friction = 0.3", "settling.sliding_friction"),
            ("climb_over = true", "settling.climb_over"),
            (
                "restitution = 0\nsliding_friction = -1",
                "settling.sliding_friction",
            ),
        ] {
            let e = resolve(text).unwrap_err().to_string();
            assert!(e.contains(key), "{text}: {e}");
            assert!(!e.contains('\n'), "{text}: {e}");
        }
    }

    #[test]
    fn fines_stick_and_coarse_particles_roll_by_the_bond_number_law() {
        let s = resolve("cohesion_diameter = 20").unwrap();
        assert!(s.sticks() && !s.is_rolling());
        // Half at d = d_c; Bo ∝ d⁻²: a tenth of d_c sticks at 100/101.
        assert!((s.sticking_at(10.0) - 0.5).abs() < 1e-15);
        assert!((s.sticking_at(1.0) - 100.0 / 101.0).abs() < 1e-15);
        assert!((s.sticking_at(100.0) - 1.0 / 101.0).abs() < 1e-15);
        assert_eq!(resolve("sticking = 0.3").unwrap().sticking_at(5.0), 0.3);
        // The exponent: half at d_c whatever n; d = 4 d_c sticks at 1/(1 + 4ⁿ).
        let s = resolve("cohesion_diameter = 20\ncohesion_exponent = 0.5").unwrap();
        assert!((s.sticking_at(10.0) - 0.5).abs() < 1e-15);
        assert!((s.sticking_at(40.0) - 1.0 / 3.0).abs() < 1e-15);
        assert!((s.sticking_at(2.5) - 2.0 / 3.0).abs() < 1e-15);
        let two = resolve("cohesion_diameter = 20\ncohesion_exponent = 2").unwrap();
        assert_eq!(two, resolve("cohesion_diameter = 20").unwrap());
    }

    #[test]
    fn restitution_turns_momentum_on_and_combines_with_sticking() {
        let s = resolve("restitution = 0\nsticking = 0.2").unwrap();
        assert!(!s.is_rolling());
        assert_eq!(
            s.momentum,
            Some(Momentum {
                restitution: 0.0,
                drop_height: None,
                sliding_friction: 0.0,
                climb_over: false,
            })
        );
        let s = resolve("restitution = 0.5\nclimb_over = true").unwrap();
        assert!(s.momentum.unwrap().climb_over);
        let s = resolve("restitution = 0.4\ndrop_height = 7").unwrap();
        assert_eq!(s.momentum.unwrap().drop_height, Some(7.0));
    }

    #[test]
    fn the_friction_angle_is_kept_as_its_sine() {
        let s = resolve("friction_angle = 30").unwrap();
        assert!((s.slope.unwrap() - 0.5).abs() < 1e-15);
        assert!((s.friction_angle().unwrap() - 30.0).abs() < 1e-12);
    }
}
