//! Command-line overrides of the common config settings, so that a config file
//! is optional. They edit the [`Config`] before it is validated, so every check
//! of the config applies to them too.

use anyhow::{bail, Result};
use clap::{Args, ValueEnum};
use packbed::config::{Config, Mode, SpeciesConfig};

/// `--mode` values.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum ModeArg {
    /// Drop and roll under gravity.
    Deposit,
    /// Random sequential addition, no gravity.
    Rsa,
}

/// The overrides of `packbed run`.
#[derive(Debug, Default, Args)]
pub struct Overrides {
    /// Dimension: 2 (discs) or 3 (spheres).
    #[arg(long, value_parser = clap::value_parser!(u8).range(2..=3))]
    pub dim: Option<u8>,
    /// Radii of the species, e.g. 10,20 (one species per radius).
    #[arg(long, value_name = "R,R,...", allow_hyphen_values = true)]
    pub radii: Option<String>,
    /// Number ratios of the species, e.g. 1,2 (one per species).
    #[arg(long, value_name = "N,N,...", allow_hyphen_values = true)]
    pub ratio: Option<String>,
    /// Make every species a rigid chain of N beads.
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    pub beads: Option<u32>,
    /// Box: thesis | W,H | W,D,H | diameters=N.
    #[arg(long = "box", value_name = "BOX", allow_hyphen_values = true)]
    pub container: Option<String>,
    /// Periodic side boundaries (no side walls).
    #[arg(long)]
    pub periodic: bool,
    /// Place exactly N particles (the roof is ignored).
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    pub count: Option<u64>,
    /// Seed of the random generator.
    #[arg(long, value_name = "S", allow_negative_numbers = true)]
    pub seed: Option<u64>,
    /// deposit (drop and roll) or rsa (random sequential addition).
    #[arg(long, value_enum)]
    pub mode: Option<ModeArg>,
    /// Percolation threshold: particles with radius >= R count as large.
    #[arg(long, value_name = "R", allow_hyphen_values = true)]
    pub large: Option<f64>,
}

/// Parses `10,20` (spaces allowed) into numbers; `usage` (e.g. `--radii 10,20`)
/// shows the expected form in errors, its first word names the option.
fn numbers(text: &str, usage: &str) -> Result<Vec<f64>> {
    let flag = usage.split(' ').next().unwrap_or(usage);
    text.split(',')
        .map(|f| {
            let f = f.trim();
            f.parse::<f64>().map_err(|_| {
                anyhow::anyhow!("{flag}: `{f}` is not a number (expected e.g. `{usage}`)")
            })
        })
        .collect()
}

fn sphere(radius: f64, ratio: f64) -> SpeciesConfig {
    // Starts from a default species so that fields added to the schema later
    // keep their defaults here too.
    let mut s = Config::default().species.swap_remove(0);
    s.name = None;
    s.radius = Some(radius);
    s.size = None;
    s.ratio = ratio;
    s
}

impl Overrides {
    /// True when no override is given.
    pub fn is_empty(&self) -> bool {
        self.dim.is_none()
            && self.radii.is_none()
            && self.ratio.is_none()
            && self.beads.is_none()
            && self.container.is_none()
            && !self.periodic
            && self.count.is_none()
            && self.seed.is_none()
            && self.mode.is_none()
            && self.large.is_none()
    }

    /// Applies the overrides to `config`.
    pub fn apply(&self, config: &mut Config) -> Result<()> {
        if let Some(d) = self.dim {
            config.dim = d;
        }
        if let Some(s) = self.seed {
            config.seed = s;
        }
        if let Some(m) = self.mode {
            config.mode = match m {
                ModeArg::Deposit => Mode::Deposit,
                ModeArg::Rsa => Mode::Rsa,
            };
        }
        self.apply_species(config)?;
        if let Some(b) = &self.container {
            apply_box(b, config)?;
        }
        if self.periodic {
            config.container.periodic = true;
        }
        if let Some(n) = self.count {
            config.fill.count = Some(n);
            config.fill.until = None;
        }
        if let Some(r) = self.large {
            config.analysis.large_radius = Some(r);
        }
        Ok(())
    }

    fn apply_species(&self, config: &mut Config) -> Result<()> {
        let radii = self
            .radii
            .as_deref()
            .map(|t| numbers(t, "--radii 10,20"))
            .transpose()?;
        let ratios = self
            .ratio
            .as_deref()
            .map(|t| numbers(t, "--ratio 1,1"))
            .transpose()?;
        if let (Some(r), Some(q)) = (&radii, &ratios) {
            if r.len() != q.len() {
                bail!(
                    "--radii has {} values but --ratio has {}: give one ratio per radius",
                    r.len(),
                    q.len()
                );
            }
        }
        if let Some(r) = &radii {
            if r.len() == config.species.len() {
                // Same number of species: keep their other settings (shape, name).
                for (s, &radius) in config.species.iter_mut().zip(r) {
                    s.radius = Some(radius);
                    s.size = None;
                }
            } else {
                config.species = r.iter().map(|&radius| sphere(radius, 1.0)).collect();
            }
        }
        if let Some(q) = &ratios {
            if q.len() != config.species.len() {
                bail!(
                    "--ratio has {} values but there are {} species (from {}): give one ratio per species",
                    q.len(),
                    config.species.len(),
                    if radii.is_some() { "--radii" } else { "the config" }
                );
            }
            for (s, &ratio) in config.species.iter_mut().zip(q) {
                s.ratio = ratio;
            }
        }
        if let Some(n) = self.beads {
            for s in &mut config.species {
                s.shape = "chain".into();
                s.beads = Some(n);
            }
        }
        Ok(())
    }
}

/// `--box thesis | W,H | W,D,H | diameters=N`.
fn apply_box(text: &str, config: &mut Config) -> Result<()> {
    let b = &mut config.container;
    let periodic = b.periodic;
    *b = Default::default();
    b.periodic = periodic;
    let text = text.trim();
    if text == "thesis" {
        b.preset = Some("thesis".into());
    } else if let Some(n) = text.strip_prefix("diameters=") {
        b.diameters = Some(numbers(n, "--box diameters=20")?[0]);
    } else {
        let v = numbers(text, "--box 400,400,400").map_err(|_| {
            anyhow::anyhow!("--box: `{text}` is not thesis, W,H, W,D,H or diameters=N")
        })?;
        match (v.as_slice(), config.dim) {
            ([w, h], _) => {
                b.width = Some(*w);
                b.height = Some(*h);
            }
            ([w, d, h], 3) => {
                b.width = Some(*w);
                b.depth = Some(*d);
                b.height = Some(*h);
            }
            ([_, _, _], dim) => bail!("--box W,D,H is for dim 3, but dim is {dim}: give W,H"),
            _ => bail!(
                "--box: `{text}` has {} numbers; give W,H (2D) or W,D,H (3D)",
                v.len()
            ),
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn apply(o: Overrides) -> Result<Config> {
        let mut c = Config::default();
        o.apply(&mut c)?;
        Ok(c)
    }

    #[test]
    fn radii_and_ratio() {
        let c = apply(Overrides {
            radii: Some("5, 7,9".into()),
            ratio: Some("1,2,3".into()),
            ..Default::default()
        })
        .unwrap();
        let r: Vec<_> = c.species.iter().map(|s| (s.radius, s.ratio)).collect();
        assert_eq!(r, [(Some(5.0), 1.0), (Some(7.0), 2.0), (Some(9.0), 3.0)]);
        c.plan::<3>().unwrap();
    }

    #[test]
    fn mismatched_lists_are_explained() {
        let e = apply(Overrides {
            radii: Some("5,7".into()),
            ratio: Some("1".into()),
            ..Default::default()
        })
        .unwrap_err();
        assert!(e.to_string().contains("--ratio has 1"), "{e}");
        let e = apply(Overrides {
            ratio: Some("1,2,3".into()),
            ..Default::default()
        })
        .unwrap_err();
        assert!(e.to_string().contains("the config"), "{e}");
    }

    #[test]
    fn bad_numbers_name_the_flag() {
        let e = apply(Overrides {
            radii: Some("10,x".into()),
            ..Default::default()
        })
        .unwrap_err();
        assert!(e.to_string().starts_with("--radii: `x`"), "{e}");
    }

    #[test]
    fn boxes() {
        let c = apply(Overrides {
            container: Some("100,200,300".into()),
            periodic: true,
            ..Default::default()
        })
        .unwrap();
        let b = &c.container;
        assert_eq!(
            (b.width, b.depth, b.height),
            (Some(100.0), Some(200.0), Some(300.0))
        );
        assert!(b.periodic);
        let c = apply(Overrides {
            container: Some("diameters=10".into()),
            ..Default::default()
        })
        .unwrap();
        assert_eq!(c.container.diameters, Some(10.0));
        let e = apply(Overrides {
            dim: Some(2),
            container: Some("1,2,3".into()),
            ..Default::default()
        })
        .unwrap_err();
        assert!(e.to_string().contains("dim 3"), "{e}");
        assert!(apply(Overrides {
            container: Some("big".into()),
            ..Default::default()
        })
        .is_err());
    }

    #[test]
    fn count_replaces_roof() {
        let mut c = Config::default();
        c.fill.until = Some("roof".into());
        Overrides {
            count: Some(50),
            ..Default::default()
        }
        .apply(&mut c)
        .unwrap();
        assert_eq!((c.fill.until, c.fill.count), (None, Some(50)));
    }
}
