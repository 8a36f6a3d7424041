//! A woven square mesh of wires as the filter medium: `[[feeds]]` with
//! `mesh = { wire_diameter, aperture }`. Its wires are placed, not fed: fixed
//! rigid chains lying straight across a periodic box, each closed on itself
//! through the periodic sides (the one kind of chain longer than the box).

use crate::container::Container;
use crate::error::{Error, Result};
use crate::math::{Real, Vector};
use crate::species::{EntryOrientation, Shape, SizeDist, Species};
use serde::{Deserialize, Serialize};

/// `mesh = { wire_diameter, aperture }`: a square mesh of straight round
/// wires, in the bed's length unit. Two layers, as a plain square weave is
/// to a sieve: wires along x on the floor, wires along y resting across
/// them, both at the pitch `aperture + wire_diameter`, so the clear opening
/// seen from above is an `aperture`-wide square (ISO 9044's w). The crimp
/// of a real weave (each wire passing over and under) is left out: it
/// changes the opening's depth, not its width. The box must be periodic
/// and its sides whole numbers of pitches, so the mesh repeats across them.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshConfig {
    /// Diameter of a wire.
    pub wire_diameter: Real,
    /// Clear opening between neighbouring wires.
    pub aperture: Real,
}

/// A woven mesh, checked: its wires' radius and pitch.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mesh {
    /// Radius of a wire.
    pub r: Real,
    /// Centre distance of neighbouring wires (aperture + diameter).
    pub pitch: Real,
}

impl Mesh {
    /// The clear opening between neighbouring wires.
    pub fn aperture(&self) -> Real {
        self.pitch - 2.0 * self.r
    }

    /// Height of the mesh's mid-plane above its bottom: where the two
    /// layers of wires touch in 3D, the wires' axes in 2D (one row of wire
    /// sections). A body whose centre lies below it has entered an opening.
    pub fn mid_plane<const D: usize>(&self) -> Real {
        if D == 3 {
            2.0 * self.r
        } else {
            self.r
        }
    }
}

/// Relative tolerance on a box side being a whole number of pitches.
const WHOLE: Real = 1e-9;

/// One family of parallel wires of a mesh: in 3D those along x (on the
/// floor) and those along y (resting across them); in 2D one row of wire
/// sections (discs), each its own body.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wires {
    /// The horizontal axis the wires run along (3D); 0 in 2D.
    pub along: usize,
    /// Parallel wires across the box.
    pub wires: u32,
    /// Beads per wire (1 in 2D).
    pub beads: u32,
    /// Centre distance of neighbouring beads of a wire, in wire radii.
    pub spacing: Real,
    /// Height of the wires' axes above the mesh's bottom.
    pub height: Real,
}

impl MeshConfig {
    /// The mesh, checked: `what` names the entry in messages.
    pub fn resolve(&self, what: &str) -> Result<Mesh> {
        let MeshConfig {
            wire_diameter: d,
            aperture: a,
        } = *self;
        if !(d.is_finite() && d > 0.0) {
            return Err(Error::config(format!(
                "{what}.mesh.wire_diameter must be a positive number, got {d}"
            )));
        }
        if !a.is_finite() {
            return Err(Error::config(format!(
                "{what}.mesh.aperture must be a number, got {a}"
            )));
        }
        if a <= 0.0 {
            return Err(Error::config(format!(
                "{what}.mesh.aperture must be above 0, got {a}: a mesh with no opening has no permeability (its wires would touch side by side)"
            )));
        }
        Ok(Mesh {
            r: 0.5 * d,
            pitch: a + d,
        })
    }
}

impl Mesh {
    /// The families of wires of this mesh in `c`; refused unless the box is
    /// periodic and each side a whole number of pitches.
    pub fn wires<const D: usize>(&self, c: &Container<D>, what: &str) -> Result<Vec<Wires>> {
        if !c.periodic {
            return Err(Error::config(format!(
                "{what}.mesh: a woven mesh repeats across the box, and walls would cut its openings short: set box.periodic = true"
            )));
        }
        let side = ["width", "depth"];
        let mut count = [0u32; 2];
        for k in 0..D - 1 {
            let l = c.size[k];
            let n = (l / self.pitch).round();
            if n < 2.0 || (n * self.pitch - l).abs() > WHOLE * l {
                let lo = (l / self.pitch).floor().max(2.0) * self.pitch;
                let hi = (l / self.pitch).ceil().max(2.0) * self.pitch;
                return Err(Error::config(format!(
                    "{what}.mesh: the box's {} ({l}) is not a whole number of pitches, at least two (aperture + wire_diameter = {}): make it {lo} or {hi}, or change the aperture",
                    side[k], self.pitch
                )));
            }
            count[k] = n as u32;
        }
        if D == 2 {
            return Ok(vec![Wires {
                along: 0,
                wires: count[0],
                beads: 1,
                spacing: 0.0,
                height: self.r,
            }]);
        }
        let family = |along: usize, across: usize, height: Real| -> Wires {
            // A wire is one rigid chain closed on itself across the periodic
            // side (no end, so no notch where a particle coarser than the
            // aperture could slip through), its beads evenly spaced at most
            // a quarter radius apart, and one bead centred over every
            // crossing. The dips between beads guide a rolling particle:
            // a dip right over the wire beneath led particles onto its
            // ridge, where they balanced against the upper wire (3-6 % of
            // a slurry finer than the aperture held); a bead there sends
            // them off it.
            let l = c.size[along];
            let per_half_pitch = (2.0 * self.pitch / self.r).ceil();
            let beads = (l / self.pitch * 2.0 * per_half_pitch).round();
            Wires {
                along,
                wires: count[across],
                beads: beads as u32,
                spacing: l / (beads * self.r),
                height,
            }
        };
        Ok(vec![family(0, 1, self.r), family(1, 0, 3.0 * self.r)])
    }

    /// The species of `family`, fed by feed `feed`.
    pub fn species(&self, family: &Wires, feed: u32) -> Species {
        let shape = if family.beads == 1 {
            Shape::Sphere
        } else {
            Shape::Chain {
                beads: family.beads,
                spacing: family.spacing,
                orientation: EntryOrientation::Horizontal,
            }
        };
        Species {
            name: format!("mesh wires along {}", ["x", "y"][family.along]),
            shape,
            size: SizeDist::Fixed(self.r),
            ratio: Real::from(family.wires),
            feed: Some(feed),
        }
    }

    /// The bodies of `family`, each as its beads' centres, the
    /// mesh's bottom on the floor.
    pub fn bodies<const D: usize>(&self, family: &Wires) -> Vec<Vec<Vector<D>>> {
        let mut out = Vec::with_capacity(family.wires as usize);
        let across = if D == 3 { 1 - family.along } else { 0 };
        for j in 0..family.wires {
            let t = (Real::from(j) + 0.5) * self.pitch;
            if D == 2 {
                let mut p = Vector([0.0; D]);
                p[0] = t;
                p[D - 1] = family.height;
                out.push(vec![p]);
                continue;
            }
            let beads = (0..family.beads)
                .map(|q| {
                    let mut p = Vector([0.0; D]);
                    p[across] = t;
                    // Bead (2j + 1)·m lies on crossing j, at (j + ½) pitches.
                    p[family.along] = Real::from(q) * family.spacing * self.r;
                    p[D - 1] = family.height;
                    p
                })
                .collect();
            out.push(beads);
        }
        out
    }
}
