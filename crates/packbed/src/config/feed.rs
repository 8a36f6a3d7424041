//! `[feed]`: where particles enter over the box. By default uniformly over
//! the floor's area (a slurry filtered evenly); from a point or along a line
//! they pour a heap or a ridge.

use crate::container::Container;
use crate::error::{Error, Result};
use crate::math::Real;
use serde::{Deserialize, Serialize};

/// How entry points spread over the box.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Pattern {
    /// Uniformly over the floor (where a body fits between the walls).
    #[default]
    Uniform,
    /// About one point: a heap (in 2D, a heap in the plane).
    Point,
    /// About a line along the depth (y) at `at[0]`: a ridge (3D; in 2D the
    /// same as a point).
    Line,
}

/// `[feed]` as written.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FeedConfig {
    /// `uniform` (default), `point` or `line`.
    #[serde(default)]
    pub pattern: Pattern,
    /// The point's horizontal position: `[x]` in 2D, `[x, y]` in 3D (a line
    /// uses x only). Default: the middle of the box.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub at: Option<Vec<Real>>,
    /// Standard deviation of the entry points about the point or line, in
    /// length units (a Gaussian in each spread direction). Default: the
    /// largest particle radius.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spread: Option<Real>,
}

impl FeedConfig {
    /// True if nothing is set: the uniform feed.
    pub fn is_default(&self) -> bool {
        *self == FeedConfig::default()
    }

    /// The feed for a box of `container` and particles up to radius `r_max`.
    pub fn resolve<const D: usize>(&self, container: &Container<D>, r_max: Real) -> Result<Feed> {
        if self.pattern == Pattern::Uniform && (self.at.is_some() || self.spread.is_some()) {
            return Err(Error::config(
                "feed.at and feed.spread place a point or line feed: set feed.pattern = \"point\" or \"line\"",
            ));
        }
        let mut at = [0.0; 2];
        for (k, a) in at.iter_mut().enumerate().take(D - 1) {
            *a = 0.5 * container.size[k];
        }
        if let Some(given) = &self.at {
            if given.len() != D - 1 {
                return Err(Error::config(format!(
                    "feed.at must hold {} horizontal coordinate{} in {D}D, got {}",
                    D - 1,
                    if D == 3 { "s" } else { "" },
                    given.len()
                )));
            }
            for (k, &x) in given.iter().enumerate() {
                if !(x.is_finite()
                    && (container.periodic || (0.0..=container.size[k]).contains(&x)))
                {
                    return Err(Error::config(format!(
                        "feed.at[{k}] = {x} is outside the box (0 to {})",
                        container.size[k]
                    )));
                }
                at[k] = x;
            }
        }
        let spread = match self.spread {
            None => r_max,
            Some(s) if s.is_finite() && s >= 0.0 => s,
            Some(s) => {
                return Err(Error::config(format!(
                    "feed.spread must be a length of at least 0, got {s}"
                )))
            }
        };
        Ok(Feed {
            pattern: self.pattern,
            at,
            spread,
        })
    }
}

/// The feed of a run, checked.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Feed {
    /// How entry points spread.
    pub pattern: Pattern,
    /// The point (x, y), or the line's x; unused coordinates are 0.
    pub at: [Real; 2],
    /// Standard deviation about it.
    pub spread: Real,
}

impl Feed {
    /// True if horizontal axis `k` is drawn about `at[k]` rather than
    /// uniformly.
    pub fn centred(&self, k: usize) -> bool {
        match self.pattern {
            Pattern::Uniform => false,
            Pattern::Point => true,
            Pattern::Line => k == 0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vector;

    fn resolve(text: &str, periodic: bool) -> Result<Feed> {
        let c = Container::<3> {
            size: Vector([10.0, 20.0, 30.0]),
            periodic,
        };
        toml::from_str::<FeedConfig>(text)
            .map_err(|e| Error::config(e.to_string()))?
            .resolve(&c, 0.5)
    }

    #[test]
    fn a_point_feed_defaults_to_the_middle_and_the_largest_radius() {
        let f = resolve("pattern = \"point\"", false).unwrap();
        assert_eq!((f.at, f.spread), ([5.0, 10.0], 0.5));
        assert!(f.centred(0) && f.centred(1));
        let l = resolve("pattern = \"line\"\nat = [2, 3]\nspread = 0", false).unwrap();
        assert!(l.centred(0) && !l.centred(1));
        assert_eq!((l.at, l.spread), ([2.0, 3.0], 0.0));
        assert_eq!(resolve("", true).unwrap().pattern, Pattern::Uniform);
    }

    #[test]
    fn bad_feeds_are_refused_with_the_key() {
        for (text, key) in [
            ("pattern = \"point\"\nat = [1]", "feed.at"),
            ("pattern = \"point\"\nat = [11, 1]", "feed.at[0]"),
            ("pattern = \"point\"\nspread = -1", "feed.spread"),
            ("pattern = \"point\"\nspread = nan", "feed.spread"),
            ("at = [1, 1]", "feed.pattern"),
            ("pattern = \"spiral\"", "spiral"),
        ] {
            let e = resolve(text, false).unwrap_err().to_string();
            assert!(e.contains(key), "{text}: {e}");
        }
    }
}
