//! The box particles settle into: floor, side walls or periodic sides, roof.

use crate::math::{Real, Vector};

/// The container: `[0, W] × [0, D] × [0, H]` (3D) or `[0, W] × [0, H]` (2D).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Container<const D: usize> {
    /// Extent along each axis; the last entry is the roof height `H`.
    pub size: Vector<D>,
    /// Periodic side boundaries (no side walls) when true.
    pub periodic: bool,
}

/// A flat, hard, frictionless boundary of the container.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Wall {
    /// The floor, `z = 0`.
    Floor,
    /// The side wall at coordinate 0 of a horizontal axis.
    Low(usize),
    /// The side wall at the far end of a horizontal axis.
    High(usize),
}

impl Wall {
    /// The name used in `wall_contacts.csv`: `floor, x0, x1, y0, y1`.
    pub fn name(&self) -> &'static str {
        const LOW: [&str; 2] = ["x0", "y0"];
        const HIGH: [&str; 2] = ["x1", "y1"];
        match self {
            Wall::Floor => "floor",
            Wall::Low(k) => LOW[*k],
            Wall::High(k) => HIGH[*k],
        }
    }
}

/// The names `box.preset` accepts.
pub const PRESETS: [&str; 1] = ["thesis"];

impl<const D: usize> Container<D> {
    /// The size of the preset box `name` (one of `PRESETS`) for particles of
    /// radius up to `r_max` in chains of up to `beads`; `None` for an unknown
    /// name. `thesis`, the source study's boxes: a cube 6 large diameters wide
    /// in 3D, a square 15 wide in 2D, stretched by `beads / 2` for 2D chains
    /// longer than two beads.
    pub(crate) fn preset_size(name: &str, r_max: Real, beads: u32) -> Option<Vector<D>> {
        match name {
            "thesis" => {
                let mut side = if D == 2 { 30.0 * r_max } else { 12.0 * r_max };
                if D == 2 && beads > 2 {
                    side *= Real::from(beads) / 2.0;
                }
                Some(Vector([side; D]))
            }
            _ => None,
        }
    }

    /// Width along horizontal axis `k`.
    #[inline]
    pub(crate) fn extent(&self, k: usize) -> Real {
        self.size[k]
    }

    /// Roof height `H`.
    #[inline]
    pub fn height(&self) -> Real {
        self.size[D - 1]
    }

    /// Area (2D) or volume (3D) of the box up to the roof.
    pub(crate) fn volume(&self) -> Real {
        self.size.0.iter().product()
    }

    /// The walls of this container: the floor, and the side walls unless periodic.
    pub(crate) fn walls(&self) -> Vec<Wall> {
        let mut w = vec![Wall::Floor];
        if !self.periodic {
            for k in 0..D - 1 {
                w.push(Wall::Low(k));
                w.push(Wall::High(k));
            }
        }
        w
    }

    /// The walls as a fixed array and their number (no allocation).
    #[inline]
    pub(crate) fn wall_array(&self) -> ([Wall; 5], usize) {
        let mut w = [Wall::Floor; 5];
        let mut n = 1;
        if !self.periodic {
            for k in 0..D - 1 {
                w[n] = Wall::Low(k);
                w[n + 1] = Wall::High(k);
                n += 2;
            }
        }
        (w, n)
    }

    /// Signed distance from `p` to the wall's surface (positive inside the box).
    #[inline]
    pub(crate) fn wall_distance(&self, wall: Wall, p: &Vector<D>) -> Real {
        match wall {
            Wall::Floor => p[D - 1],
            Wall::Low(k) => p[k],
            Wall::High(k) => self.size[k] - p[k],
        }
    }

    /// The inward unit normal of a wall.
    #[inline]
    pub(crate) fn wall_normal(&self, wall: Wall) -> Vector<D> {
        match wall {
            Wall::Floor => Vector::up(),
            Wall::Low(k) => Vector::axis(k),
            Wall::High(k) => -Vector::axis(k),
        }
    }

    /// Coordinate `x` along horizontal axis `k` of a periodic box brought into
    /// `[0, w)`. The one wrap of the crate: beds are written with it, so every
    /// reader of a bed sees the same coordinates (a tiny negative `x` whose image
    /// rounds to `w` itself is put at 0).
    #[inline]
    pub(crate) fn wrap_coordinate(&self, k: usize, x: Real) -> Real {
        let w = self.size[k];
        let y = x - w * (x / w).floor();
        if y >= w {
            0.0
        } else {
            y
        }
    }

    /// The point `p` with its horizontal coordinates brought into the box on
    /// periodic sides (unchanged between walls).
    #[inline]
    pub(crate) fn wrap(&self, mut p: Vector<D>) -> Vector<D> {
        if self.periodic {
            for k in 0..D - 1 {
                p[k] = self.wrap_coordinate(k, p[k]);
            }
        }
        p
    }

    /// Shortest displacement `b − a`, taking periodic sides into account.
    #[inline]
    pub fn displacement(&self, a: &Vector<D>, b: &Vector<D>) -> Vector<D> {
        let mut d = *b - *a;
        if self.periodic {
            for k in 0..D - 1 {
                let w = self.size[k];
                d[k] -= w * (d[k] / w).round();
            }
        }
        d
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_thesis_boxes_are_six_diameters_in_3d_and_fifteen_in_2d() {
        let cube = Container::<3>::preset_size("thesis", 10.0, 1).unwrap();
        assert_eq!(cube.0, [120.0; 3]);
        let square = Container::<2>::preset_size("thesis", 10.0, 2).unwrap();
        assert_eq!(square.0, [300.0; 2]);
        // 2D chains of 6 beads stretch it threefold; 3D chains do not.
        let stretched = Container::<2>::preset_size("thesis", 10.0, 6).unwrap();
        assert_eq!(stretched.0, [900.0; 2]);
        assert_eq!(
            Container::<3>::preset_size("thesis", 10.0, 6).unwrap().0,
            [120.0; 3]
        );
        assert!(Container::<3>::preset_size("large", 10.0, 1).is_none());
        assert!(PRESETS
            .iter()
            .all(|p| Container::<2>::preset_size(p, 1.0, 1).is_some()));
    }
}
