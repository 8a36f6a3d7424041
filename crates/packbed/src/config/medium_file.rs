//! A filter medium read from a bed file: `[[feeds]]` with `file =
//! "medium.csv"` (relative to the config file). The file's particles (a
//! sintered plate, a precoat built by an earlier run, a scan) are placed
//! exactly as read, bodies kept, fixed, and lifted above the open floor as
//! every medium is ([`Plan::medium_gap`](super::Plan::medium_gap)).
//!
//! The plan names the file; its particles are read where files are read
//! (`io::read::medium`, when a run is planned: `pipeline::planned`), which
//! hands them to [`Plan::lay_medium_file`] here: the species of the file,
//! the feed's count, and the check that the medium leaves room above it.

use crate::error::{Error, Result};
use crate::math::Real;
use crate::species::{Shape, SizeDist, SizeTable, Species};
use std::path::PathBuf;
use std::sync::Arc;

/// A medium's bed file, and once read its particles.
#[derive(Clone, Debug, PartialEq)]
pub struct MediumFile {
    /// The file (made absolute or relative to the working directory, as the
    /// config's other paths).
    pub path: PathBuf,
    /// Its particles, once read; `None` in a plan of `Config::plan` alone.
    pub beads: Option<Arc<MediumBeads>>,
}

/// The particles of a medium file, in the engine's terms: each body's beads
/// one after another, bodies numbered from 0, species as plan indices.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MediumBeads {
    /// Centres as read (the first `D` components), on the solid floor.
    pub centres: Vec<[Real; 3]>,
    /// Radii as read.
    pub radii: Vec<Real>,
    /// Species (indices into the plan's species).
    pub species: Vec<u32>,
    /// Bodies, from 0, in order of first appearance in the file.
    pub bodies: Vec<u32>,
}

impl<const D: usize> super::Plan<D> {
    /// Gives feed `k`, a medium file, the particles read from it (`centres`
    /// with `D` components used, `radii`, the file's `species` indices and
    /// `bodies`): one species per species index of the file, named `medium
    /// file <index>`, of the file's radius (a table of the file's radii
    /// where they differ, each by its number), a ratio of its bodies; the
    /// beads of each body kept together. Refused when the medium, lifted above the open
    /// floor, reaches the box's roof: the later feeds need the room above it.
    pub fn lay_medium_file(
        &mut self,
        k: usize,
        centres: &[[Real; 3]],
        radii: &[Real],
        species: &[u32],
        bodies: &[u32],
    ) -> Result<()> {
        let what = format!("feeds[{k}].file");
        let Some(file) = self.feeds.get(k).and_then(|f| f.file.as_ref()) else {
            return Err(Error::config(format!("{what}: feed {k} reads no file")));
        };
        let source = file.path.clone();
        let path = source.display().to_string();
        let n = radii.len();
        // Bodies in order of first appearance, each one's beads together.
        let mut rank = vec![0usize; n];
        let mut seen: std::collections::HashMap<u32, usize> = Default::default();
        for (i, &b) in bodies.iter().enumerate() {
            let next = seen.len();
            rank[i] = *seen.entry(b).or_insert(next);
        }
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by_key(|&i| (rank[i], i));
        // One species per species index of the file, in increasing order.
        let mut ids: Vec<u32> = species.to_vec();
        ids.sort_unstable();
        ids.dedup();
        let base = self.species.len() as u32;
        let mut feed_species = Vec::with_capacity(ids.len());
        for (j, &id) in ids.iter().enumerate() {
            let of = |i: &usize| species[*i] == id;
            let (lo, hi) = (0..n)
                .filter(of)
                .map(|i| radii[i])
                .fold((Real::INFINITY, 0.0), |(lo, hi): (Real, Real), r| {
                    (lo.min(r), hi.max(r))
                });
            let mut own: Vec<usize> = (0..n).filter(of).map(|i| rank[i]).collect();
            own.sort_unstable();
            own.dedup();
            let name = format!("medium file {id}");
            if self.species.iter().any(|s| s.name == name) {
                return Err(Error::config(format!(
                    "species `{name}`: that name is the medium file's ({what}); rename the species"
                )));
            }
            self.species.push(Species {
                name,
                shape: Shape::Sphere,
                size: if lo == hi {
                    SizeDist::Fixed(lo)
                } else {
                    let own: Vec<Real> = (0..n).filter(of).map(|i| radii[i]).collect();
                    SizeDist::Table(SizeTable::of_radii(&own, &source))
                },
                ratio: own.len() as Real,
                feed: Some(k as u32),
            });
            feed_species.push(base + j as u32);
        }
        let beads = MediumBeads {
            centres: order.iter().map(|&i| centres[i]).collect(),
            radii: order.iter().map(|&i| radii[i]).collect(),
            species: order
                .iter()
                .map(|&i| base + ids.binary_search(&species[i]).unwrap_or(0) as u32)
                .collect(),
            bodies: order.iter().map(|&i| rank[i] as u32).collect(),
        };
        let feed = &mut self.feeds[k];
        feed.species = feed_species;
        feed.count = n as u64;
        if let Some(f) = feed.file.as_mut() {
            f.beads = Some(Arc::new(beads));
        }
        self.fill = super::Fill::Count(self.feeds.iter().map(|f| f.count).sum());
        // The medium stands on the open floor `lift` above it.
        let top = (0..n)
            .map(|i| centres[i][D - 1] + radii[i])
            .fold(Real::NEG_INFINITY, Real::max);
        let lift = self.medium_gap();
        let roof = self.container.height();
        if top + lift >= roof {
            return Err(Error::config(format!(
                "{what}: the medium of {path} stands {} high (its top {top} lifted {lift} above the open floor), \
                 reaching the roof (box.height = {roof}): the feed region, where the later feeds settle, starts \
                 at the medium's top and must lie inside the box, so make box.height larger than {}",
                top + lift,
                top + lift
            )));
        }
        Ok(())
    }
}
