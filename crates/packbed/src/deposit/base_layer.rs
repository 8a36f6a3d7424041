//! The base layer: particles resting on the floor at random places until the floor
//! is saturated, then a sweep that fills every gap still wide enough for the
//! smallest particle (as the source study seeded its beds).

use super::roll::Terrain;
use crate::container::Wall;
use crate::geometry::{intersection_points, Surface};
use crate::math::{Real, Vector};

/// True if a sphere of radius `r` centred at `p` overlaps nothing by more than
/// `slack` (walls and fixed particles; the floor is the caller's business).
pub(crate) fn fits<const D: usize>(
    terrain: &Terrain<'_, D>,
    p: &Vector<D>,
    r: Real,
    slack: Real,
) -> bool {
    let c = terrain.container;
    if !c.periodic {
        for k in 0..D - 1 {
            if p[k] < r - slack || p[k] > c.size[k] - r + slack {
                return false;
            }
        }
    }
    let overlaps = |reach: Real| {
        let (mut lo, mut hi) = (*p, *p);
        for k in 0..D {
            lo[k] -= reach;
            hi[k] += reach;
        }
        terrain.grid.any_in_box(&lo, &hi, |id, shift, _| {
            let q = terrain.centres[id as usize] + shift;
            let need = r + terrain.radii[id as usize] - slack;
            (*p - q).norm2() < need * need
        })
    };
    // On a nearly saturated floor almost every trial fails, mostly on a close
    // neighbour: the few cells within reach of a particle of the same size are
    // looked at first, the whole reach of the largest only if they are free.
    let reach = r + terrain.r_fixed_max;
    !((2.0 * r < reach && overlaps(2.0 * r)) || overlaps(reach))
}

/// Candidate resting places on the floor for a particle of radius `r` that
/// touch the floor particle `j` (or, with `j = None`, only walls): the points where
/// the floor plane meets `D − 1` other surfaces, one of which is particle `j`.
pub(crate) fn floor_vertices<const D: usize>(
    terrain: &Terrain<'_, D>,
    j: Option<u32>,
    r: Real,
    out: &mut Vec<Vector<D>>,
) {
    out.clear();
    let c = terrain.container;
    let floor = Surface::Plane {
        normal: Vector::up(),
        offset: r,
    };
    let mut walls: Vec<Surface<D>> = Vec::new();
    if !c.periodic {
        for k in 0..D - 1 {
            walls.push(plane(c.wall_normal(Wall::Low(k)), r));
            walls.push(plane(c.wall_normal(Wall::High(k)), r - c.size[k]));
        }
    }
    let push_points = |s: &[Surface<D>], out: &mut Vec<Vector<D>>| {
        let (pts, n) = intersection_points(s);
        out.extend_from_slice(&pts[..n]);
    };
    let Some(j) = j else {
        // Corners: the floor with D − 1 walls of different axes (2D: one wall).
        if D == 2 {
            for w in &walls {
                let mut s = [floor; D];
                s[1] = *w;
                corner_point(&s, out);
            }
        } else if walls.len() == 4 {
            for a in 0..2 {
                for b in 2..4 {
                    let mut s = [floor; D];
                    s[1] = walls[a];
                    s[D - 1] = walls[b];
                    corner_point(&s, out);
                }
            }
        }
        return;
    };
    let cj = terrain.centres[j as usize];
    let ball_j = Surface::Ball {
        centre: cj,
        radius: r + terrain.radii[j as usize],
    };
    if D == 2 {
        let mut s = [floor; D];
        s[1] = ball_j;
        push_points(&s, out);
        return;
    }
    // 3D: particle j with a wall, or with a neighbour (periodic images included).
    for w in &walls {
        let mut s = [floor; D];
        s[1] = ball_j;
        s[D - 1] = *w;
        push_points(&s, out);
    }
    let reach = 2.0 * (r + terrain.r_fixed_max);
    let (mut lo, mut hi) = (cj, cj);
    for k in 0..D - 1 {
        lo[k] -= reach;
        hi[k] += reach;
    }
    lo[D - 1] = 0.0;
    hi[D - 1] = 2.0 * terrain.r_fixed_max;
    let mut others = Vec::new();
    terrain.grid.for_each_in_box(&lo, &hi, |id, shift, _| {
        if id != j || shift != Vector::zero() {
            let q = terrain.centres[id as usize] + shift;
            others.push(Surface::Ball {
                centre: q,
                radius: r + terrain.radii[id as usize],
            });
        }
    });
    for o in others {
        let mut s = [floor; D];
        s[1] = ball_j;
        s[D - 1] = o;
        push_points(&s, out);
    }
}

fn plane<const D: usize>(normal: Vector<D>, offset: Real) -> Surface<D> {
    Surface::Plane { normal, offset }
}

/// The point where `D` axis-aligned planes meet.
fn corner_point<const D: usize>(s: &[Surface<D>; D], out: &mut Vec<Vector<D>>) {
    let mut p = Vector::<D>::zero();
    for surf in s {
        if let Surface::Plane { normal, offset } = surf {
            // Axis-aligned unit normal: the coordinate is ±offset on its axis.
            for k in 0..D {
                if normal[k] != 0.0 {
                    p[k] = offset / normal[k];
                }
            }
        }
    }
    out.push(p);
}
