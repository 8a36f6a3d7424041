//! contacts

use crate::container::Wall;
use crate::math::Real;

/// Two touching particles (`i < j`) and the gap between their surfaces.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// Smaller particle id.
    pub i: u32,
    /// Larger particle id.
    pub j: u32,
    /// Surface gap (negative: overlap).
    pub gap: Real,
}

/// A particle touching the floor or a side wall.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WallContact {
    /// Particle id.
    pub i: u32,
    /// Which wall.
    pub wall: Wall,
    /// Gap between the particle's surface and the wall.
    pub gap: Real,
}

/// All contacts of a bed.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Contacts {
    /// Particle–particle contacts, sorted by `(i, j)`.
    pub pairs: Vec<Contact>,
    /// Particle–wall contacts, sorted by particle then wall.
    pub walls: Vec<WallContact>,
}
