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
    pub fn r_max(&self) -> Real {
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
