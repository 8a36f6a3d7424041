//! Obstacles met by the moving particle: fixed particles (as periodic images) and
//! the container's planes, each with an identity so that contacts can be tracked.

use crate::container::{Container, Wall};
use crate::geometry::Surface;
use crate::math::Real;

/// An inflated obstacle and who it is.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Obstacle<const D: usize> {
    /// The surface the moving centre must stay outside of.
    pub surface: Surface<D>,
    /// Identity: particle id and periodic image, or a wall.
    pub key: u64,
}

/// Identity of particle `id` seen through the periodic image with code `image`
/// (as given by the grid).
#[inline]
pub(crate) fn particle_key(id: u32, image: u16) -> u64 {
    ((id as u64) << 16) | image as u64
}

/// Identity of a wall.
#[inline]
pub(crate) fn wall_key(wall: Wall) -> u64 {
    u64::MAX
        - match wall {
            Wall::Floor => 0,
            Wall::Low(k) => 1 + 2 * k as u64,
            Wall::High(k) => 2 + 2 * k as u64,
        }
}

/// True if the key is the floor's.
#[inline]
pub(crate) fn is_floor(key: u64) -> bool {
    key == wall_key(Wall::Floor)
}

/// The plane a wall presents to the centre of a particle of radius `r`.
#[inline]
pub(crate) fn wall_obstacle<const D: usize>(c: &Container<D>, wall: Wall, r: Real) -> Obstacle<D> {
    let normal = c.wall_normal(wall);
    let offset = match wall {
        Wall::Floor | Wall::Low(_) => r,
        Wall::High(k) => r - c.size[k],
    };
    Obstacle {
        surface: Surface::Plane { normal, offset },
        key: wall_key(wall),
    }
}
