//! The `Bed`: the one hand-off type between deposition, file readers, analysis and
//! renderers. Particles are stored as structure of arrays, in deposition order.

use crate::container::Container;
use crate::math::{ball_volume, Real, Vector};
use crate::species::Species;

/// A packed bed: the box and its particles (spheres or beads of chains).
#[derive(Clone, Debug)]
pub struct Bed<const D: usize> {
    /// The box.
    pub container: Container<D>,
    /// Centre of each particle.
    pub centres: Vec<Vector<D>>,
    /// Radius of each particle.
    pub radii: Vec<Real>,
    /// Species index of each particle (into `species`).
    pub species: Vec<u32>,
    /// Body index of each particle (beads of one chain share it).
    pub bodies: Vec<u32>,
    /// The species of this bed (names and sizes, for reports).
    pub species_info: Vec<Species>,
}

#[cfg(test)]
impl Bed<2> {
    /// Discs `(x, y, r)` of species 0: the hand-made beds of unit tests.
    pub(crate) fn of_discs(size: [Real; 2], periodic: bool, discs: &[(Real, Real, Real)]) -> Self {
        Bed::of_spheres(
            size,
            periodic,
            discs.iter().map(|&(x, y, r)| ([x, y], r, 0)),
        )
    }
}

/// A body that passed the filter medium: it reached the open floor.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Filtrate {
    /// Its species.
    pub species: u32,
    /// Its (bead) radius.
    pub radius: Real,
    /// Its beads (1 for a sphere).
    pub beads: u32,
    /// Where it left: the horizontal position of its lowest bead on the
    /// floor (x, and y in 3D; 0 for the axes a 2D bed lacks).
    pub at: [Real; 2],
}

/// A bed of either dimension: the one place the dimension is chosen at run time.
#[derive(Clone, Debug)]
pub enum AnyBed {
    /// A 2D bed of discs.
    D2(Bed<2>),
    /// A 3D bed of spheres.
    D3(Bed<3>),
}

impl<const D: usize> Bed<D> {
    /// An empty bed in this container.
    pub fn new(container: Container<D>, species_info: Vec<Species>) -> Self {
        Bed {
            container,
            centres: Vec::new(),
            radii: Vec::new(),
            species: Vec::new(),
            bodies: Vec::new(),
            species_info,
        }
    }

    /// A bed of single spheres `(centre, radius, species)` in a box of `size`,
    /// with no species described: hand-made beds for checks and examples.
    pub fn of_spheres(
        size: [Real; D],
        periodic: bool,
        spheres: impl IntoIterator<Item = ([Real; D], Real, u32)>,
    ) -> Self {
        let mut bed = Bed::new(
            Container {
                size: Vector(size),
                periodic,
            },
            Vec::new(),
        );
        for (c, r, s) in spheres {
            bed.push(Vector(c), r, s);
        }
        bed
    }

    /// Number of particles (spheres or beads).
    pub fn len(&self) -> usize {
        self.centres.len()
    }

    /// True when the bed has no particle.
    pub fn is_empty(&self) -> bool {
        self.centres.is_empty()
    }

    /// Number of distinct bodies (a sphere is a body of one bead).
    pub fn body_count(&self) -> usize {
        // Bed files may number bodies sparsely (molecule ids of a DEM export),
        // so the largest id + 1 is not the count.
        let mut ids = self.bodies.clone();
        ids.sort_unstable();
        ids.dedup();
        ids.len()
    }

    /// The bed in a few words, for titles: `3D bed, 1200 spheres in 240
    /// bodies, periodic sides`.
    #[cfg_attr(not(feature = "render"), allow(dead_code))]
    pub(crate) fn describe(&self) -> String {
        let what = match (D, self.len()) {
            (2, 1) => "disc",
            (2, _) => "discs",
            (_, 1) => "sphere",
            _ => "spheres",
        };
        let mut t = format!("{D}D bed, {} {what}", self.len());
        let bodies = self.body_count();
        if bodies != self.len() {
            let noun = if bodies == 1 { "body" } else { "bodies" };
            t.push_str(&format!(" in {bodies} {noun}"));
        }
        if self.container.periodic {
            t.push_str(", periodic sides");
        }
        t
    }

    /// Appends a particle that is a body of its own (numbered after the last body).
    pub fn push(&mut self, centre: Vector<D>, radius: Real, species: u32) {
        let body = self.bodies.last().map_or(0, |&b| b + 1);
        self.push_bead(centre, radius, species, body);
    }

    /// Appends a particle belonging to body `body`.
    pub fn push_bead(&mut self, centre: Vector<D>, radius: Real, species: u32, body: u32) {
        self.centres.push(centre);
        self.radii.push(radius);
        self.species.push(species);
        self.bodies.push(body);
    }

    /// Largest particle radius (0 for an empty bed).
    pub(crate) fn r_max(&self) -> Real {
        self.radii.iter().copied().fold(0.0, Real::max)
    }

    /// Smallest particle radius (0 for an empty bed).
    pub fn r_min(&self) -> Real {
        if self.radii.is_empty() {
            0.0
        } else {
            self.radii.iter().copied().fold(Real::INFINITY, Real::min)
        }
    }

    /// Height of the highest particle top (0 for an empty bed).
    pub fn top(&self) -> Real {
        self.centres
            .iter()
            .zip(&self.radii)
            .map(|(c, r)| c.height() + r)
            .fold(0.0, Real::max)
    }

    /// Total solid volume (area in 2D), each particle counted whole.
    pub fn solid_volume(&self) -> Real {
        self.radii.iter().map(|&r| ball_volume::<D>(r)).sum()
    }
}

impl<const D: usize> Bed<D> {
    /// This bed as a 2D bed, when it is one. With [`Bed::as_3d`], the one
    /// place generic code learns its dimension (2D-only measures such as the
    /// voids, the 2D and 3D pictures), without copying the bed.
    pub(crate) fn as_2d(&self) -> Option<&Bed<2>> {
        (self as &dyn std::any::Any).downcast_ref()
    }

    /// This bed as a 3D bed, when it is one.
    #[cfg_attr(not(feature = "render"), allow(dead_code))]
    pub(crate) fn as_3d(&self) -> Option<&Bed<3>> {
        (self as &dyn std::any::Any).downcast_ref()
    }
}

/// Runs `$body` with `$b` bound to the bed inside an [`AnyBed`], whatever its
/// dimension: the one match on the dimension of the bed's methods (here and
/// in the measures, [`crate::analysis`]).
macro_rules! each_dim {
    ($bed:expr, $b:ident => $body:expr) => {
        match $bed {
            $crate::bed::AnyBed::D2($b) => $body,
            $crate::bed::AnyBed::D3($b) => $body,
        }
    };
}
pub(crate) use each_dim;

impl AnyBed {
    /// Wraps a bed of dimension 2 or 3 (the only ones packbed builds or reads).
    pub fn from_bed<const D: usize>(bed: Bed<D>) -> Option<AnyBed> {
        let any: Box<dyn std::any::Any> = Box::new(bed);
        match any.downcast::<Bed<2>>() {
            Ok(b) => Some(AnyBed::D2(*b)),
            Err(any) => any.downcast::<Bed<3>>().ok().map(|b| AnyBed::D3(*b)),
        }
    }

    /// 2 or 3.
    pub fn dim(&self) -> u8 {
        each_dim!(self, b => b.container.size.0.len() as u8)
    }

    /// Number of particles (spheres, discs or beads).
    pub fn len(&self) -> usize {
        each_dim!(self, b => b.len())
    }

    /// True when the bed holds no particle.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Number of bodies (a chain is one body).
    pub(crate) fn body_count(&self) -> usize {
        each_dim!(self, b => b.body_count())
    }

    /// True when the side boundaries are periodic.
    pub fn periodic(&self) -> bool {
        each_dim!(self, b => b.container.periodic)
    }

    /// The box extents: `[W, H]` or `[W, D, H]` (the last is the height).
    pub fn size(&self) -> Vec<Real> {
        each_dim!(self, b => b.container.size.0.to_vec())
    }

    /// The particle centres as rows of `dim()` coordinates, one after another
    /// (x, y[, z] of particle 0, then particle 1, …), as `particles.csv` has them.
    pub fn positions(&self) -> Vec<Real> {
        each_dim!(self, b => b.centres.iter().flat_map(|c| c.0).collect())
    }

    /// Radius of each particle.
    pub fn radii(&self) -> &[Real] {
        each_dim!(self, b => &b.radii)
    }

    /// Species index of each particle.
    pub fn species(&self) -> &[u32] {
        each_dim!(self, b => &b.species)
    }

    /// Body index of each particle (the beads of a chain share it).
    pub fn bodies(&self) -> &[u32] {
        each_dim!(self, b => &b.bodies)
    }

    /// The feed of each particle, for a bed built from `[[feeds]]` (the
    /// `feed` column of `particles.csv`); `None` for a bed of one feed.
    pub fn feeds(&self) -> Option<Vec<u32>> {
        let of_species = feed_of_species(self.species_info())?;
        Some(
            self.species()
                .iter()
                .map(|&s| of_species[s as usize])
                .collect(),
        )
    }

    /// The species of the bed (names and sizes).
    pub fn species_info(&self) -> &[Species] {
        each_dim!(self, b => &b.species_info)
    }

    /// Total solid volume (area in 2D).
    pub fn solid_volume(&self) -> Real {
        each_dim!(self, b => b.solid_volume())
    }
}

/// The feed of each species, if the bed was built from `[[feeds]]` (every
/// species then has one).
pub(crate) fn feed_of_species(species: &[Species]) -> Option<Vec<u32>> {
    species
        .iter()
        .map(|s| s.feed)
        .collect::<Option<Vec<u32>>>()
        .filter(|f| !f.is_empty())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bed_describes_its_particles_bodies_and_sides() {
        let one = Bed::of_discs([10.0, 10.0], false, &[(5.0, 1.0, 1.0)]);
        assert_eq!(one.describe(), "2D bed, 1 disc");
        let mut two = Bed::of_discs([10.0, 10.0], true, &[(2.0, 1.0, 1.0), (4.0, 1.0, 1.0)]);
        assert_eq!(two.describe(), "2D bed, 2 discs, periodic sides");
        two.bodies = vec![0, 0];
        assert_eq!(two.describe(), "2D bed, 2 discs in 1 body, periodic sides");
    }
}
