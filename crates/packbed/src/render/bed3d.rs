//! 3D beds: a shaded raster of the exact sphere surfaces.
//!
//! Orthographic view (so the scale bar holds everywhere in the image plane).
//! Each sphere is projected to a disc; every pixel of the disc gets the depth of
//! the sphere's front surface, `depth(centre) − sqrt(R² − dx² − dy²)` (exactly the
//! ray–sphere hit of that pixel's ray), and a z-buffer keeps the nearest. Ties go
//! to the lower particle id, so the image does not depend on the order in which
//! threads draw. The image is cut into bands of rows drawn in parallel (rayon),
//! each band with the spheres that overlap it. Shading: ambient, Lambert diffuse
//! and a small specular highlight from a light above and to the left; outlines
//! where a sphere's silhouette lies in front of something else. Supersampling
//! (2 × 2 by default) antialiases edges.

use super::canvas::{PngCanvas, Rgb};
use super::frame;
use super::{contacts_if_needed, default_title, picture_palette, RenderOptions};
use crate::bed::Bed;
use crate::error::{Error, Result};
use crate::math::v3::{cross, dot};
use rayon::prelude::*;

/// The viewing direction: where the camera sits, seen from the box centre.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// Degrees from the front (−y side) towards +x.
    pub azimuth: f64,
    /// Degrees above the horizontal (90: straight down).
    pub elevation: f64,
}

impl Default for View {
    /// An oblique view from the front left, 30° above the horizontal.
    fn default() -> Self {
        View {
            azimuth: -30.0,
            elevation: 30.0,
        }
    }
}

impl View {
    /// Refuses non-finite angles and elevations outside [−90°, 90°].
    pub fn check(&self) -> Result<()> {
        if !(self.azimuth.is_finite() && self.elevation.is_finite() && self.elevation.abs() <= 90.0)
        {
            return Err(Error::Impossible(format!(
                "view azimuth {}°, elevation {}°: the elevation must be within −90° to 90°",
                self.azimuth, self.elevation
            )));
        }
        Ok(())
    }

    /// Unit vectors: towards the camera (`eye`), image right and image up.
    pub fn basis(&self) -> [[f64; 3]; 3] {
        let (a, e) = (self.azimuth.to_radians(), self.elevation.to_radians());
        let eye = [a.sin() * e.cos(), -a.cos() * e.cos(), e.sin()];
        // Straight down, "up" in the image is the +y axis turned by the azimuth.
        let right = if e.cos() > 1e-9 {
            normalize(cross([0.0, 0.0, 1.0], eye))
        } else {
            [a.cos(), a.sin(), 0.0]
        };
        let up = cross(eye, right);
        [eye, right, up]
    }
}

/// Part of the bed to keep, so that the inside shows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Cut {
    /// The whole bed.
    None,
    /// The back half: particles whose centre lies behind the vertical plane
    /// through the box centre facing the camera.
    Half,
    /// Particles whose centre coordinate along `axis` lies in `[lo, hi]`.
    Slab {
        /// 0 = x, 1 = y, 2 = z.
        axis: usize,
        /// Lower bound.
        lo: f64,
        /// Upper bound.
        hi: f64,
    },
}

impl std::str::FromStr for View {
    type Err = String;

    /// `AZIMUTH,ELEVATION` in degrees, e.g. `-30,30`.
    fn from_str(text: &str) -> std::result::Result<View, String> {
        match crate::config::parse_numbers(text)?.as_slice() {
            [a, e] if a.is_finite() && e.is_finite() => Ok(View {
                azimuth: *a,
                elevation: *e,
            }),
            _ => Err(format!("`{text}`: give AZIMUTH,ELEVATION in degrees")),
        }
    }
}

impl std::str::FromStr for Cut {
    type Err = String;

    /// `half`, or a slab `x:LO:HI`, `y:LO:HI`, `z:LO:HI`.
    fn from_str(t: &str) -> std::result::Result<Cut, String> {
        if t == "half" {
            return Ok(Cut::Half);
        }
        let usage = || format!("`{t}`: give half, or x:LO:HI, y:LO:HI, z:LO:HI");
        let parts: Vec<&str> = t.split(':').collect();
        let axis = match parts.as_slice() {
            ["x", _, _] => 0,
            ["y", _, _] => 1,
            ["z", _, _] => 2,
            _ => return Err(usage()),
        };
        let bound = |p: &str| match p.trim().parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(format!("`{t}`: \"{p}\" is not a finite number")),
        };
        let (lo, hi) = (bound(parts[1])?, bound(parts[2])?);
        if lo >= hi {
            return Err(format!("`{t}`: LO must be below HI"));
        }
        Ok(Cut::Slab { axis, lo, hi })
    }
}

fn normalize(a: [f64; 3]) -> [f64; 3] {
    let n = dot(a, a).sqrt();
    [a[0] / n, a[1] / n, a[2] / n]
}

/// A sphere projected into the (supersampled) image.
#[derive(Clone, Copy)]
struct Disc {
    x: f32,
    y: f32,
    /// Depth of the centre (larger is farther), in pixels.
    depth: f32,
    r: f32,
    id: u32,
}

/// The z-buffer: depth and particle id per sample (`u32::MAX`: background).
struct ZBuffer {
    w: usize,
    h: usize,
    depth: Vec<f32>,
    id: Vec<u32>,
}

/// Rows per band of parallel work (before supersampling).
const BAND: usize = 16;

/// Draws the spheres into a z-buffer of `w × h` samples.
fn rasterise(discs: &[Disc], w: usize, h: usize) -> ZBuffer {
    let band = BAND;
    let bands = h.div_ceil(band);
    // Bin the discs by band (counting sort, in id order: deterministic).
    let band_range = |d: &Disc| -> (usize, usize) {
        let y0 = ((d.y - d.r).floor().max(0.0) as usize) / band;
        let y1 = (((d.y + d.r).ceil().max(0.0) as usize).min(h.saturating_sub(1))) / band;
        (y0, y1)
    };
    let mut count = vec![0usize; bands + 1];
    for d in discs {
        let (a, b) = band_range(d);
        for k in a..=b.min(bands - 1) {
            count[k + 1] += 1;
        }
    }
    for k in 0..bands {
        count[k + 1] += count[k];
    }
    let mut fill = count.clone();
    let mut members = vec![0u32; count[bands]];
    for (i, d) in discs.iter().enumerate() {
        let (a, b) = band_range(d);
        for k in a..=b.min(bands - 1) {
            members[fill[k]] = i as u32;
            fill[k] += 1;
        }
    }

    let mut depth = vec![f32::INFINITY; w * h];
    let mut id = vec![u32::MAX; w * h];
    depth
        .par_chunks_mut(w * band)
        .zip(id.par_chunks_mut(w * band))
        .enumerate()
        .for_each(|(k, (zb, ib))| {
            let row0 = k * band;
            let rows = zb.len() / w;
            for &m in &members[count[k]..count[k + 1]] {
                let d = discs[m as usize];
                let r2 = d.r * d.r;
                let ya = ((d.y - d.r).floor().max(row0 as f32) as usize).max(row0);
                let yb = ((d.y + d.r).ceil() as usize).min(row0 + rows);
                for y in ya..yb {
                    // Sample at the pixel centre.
                    let dy = y as f32 + 0.5 - d.y;
                    let hw2 = r2 - dy * dy;
                    if hw2 <= 0.0 {
                        continue;
                    }
                    let hw = hw2.sqrt();
                    let xa = (d.x - hw - 0.5).ceil().max(0.0) as usize;
                    let xb = ((d.x + hw - 0.5).floor() + 1.0).clamp(0.0, w as f32) as usize;
                    let line = (y - row0) * w;
                    for x in xa..xb {
                        let dx = x as f32 + 0.5 - d.x;
                        let dz2 = hw2 - dx * dx;
                        if dz2 < 0.0 {
                            continue;
                        }
                        let z = d.depth - dz2.sqrt();
                        let p = line + x;
                        if z < zb[p] || (z == zb[p] && d.id < ib[p]) {
                            zb[p] = z;
                            ib[p] = d.id;
                        }
                    }
                }
            }
        });
    ZBuffer { w, h, depth, id }
}

/// Shaded colour of sample `(x, y)` of sphere `d` with base colour `c`.
fn shade(d: &Disc, x: usize, y: usize, c: Rgb, light: [f64; 3], half: [f64; 3]) -> [f32; 3] {
    let nx = (x as f64 + 0.5 - d.x as f64) / d.r as f64;
    let ny = -(y as f64 + 0.5 - d.y as f64) / d.r as f64;
    let nz = (1.0 - nx * nx - ny * ny).max(0.0).sqrt();
    let n = [nx, ny, nz];
    let diffuse = dot(n, light).max(0.0);
    let spec = dot(n, half).max(0.0).powi(40);
    let k = 0.45 + 0.55 * diffuse;
    let base = [c.0 as f64, c.1 as f64, c.2 as f64];
    let mut out = [0.0f32; 3];
    for i in 0..3 {
        out[i] = (base[i] * k + 255.0 * 0.25 * spec).min(255.0) as f32;
    }
    out
}

/// The PNG picture of a 3D bed.
pub fn png(bed: &Bed<3>, opts: &RenderOptions) -> Result<Vec<u8>> {
    let contacts = contacts_if_needed(bed, opts);
    let pal = picture_palette(bed, opts, contacts.as_ref())?;
    let mut fr = frame::layout(opts.width, opts.height, &pal);
    fr.length_unit = super::run_plots::length_label(opts.length_unit);
    let [eye, right, up] = opts.view.basis();
    let size = bed.container.size;
    let height = size[2].max(bed.top());
    let centre = [size[0] / 2.0, size[1] / 2.0, height / 2.0];

    // Fit the projected box corners into the picture area.
    let corners: Vec<[f64; 3]> = (0..8)
        .map(|k| {
            [
                if k & 1 == 0 { 0.0 } else { size[0] },
                if k & 2 == 0 { 0.0 } else { size[1] },
                if k & 4 == 0 { 0.0 } else { height },
            ]
        })
        .collect();
    let proj = |p: [f64; 3]| {
        let q = [p[0] - centre[0], p[1] - centre[1], p[2] - centre[2]];
        (dot(q, right), dot(q, up), -dot(q, eye))
    };
    let (mut u0, mut u1, mut v0, mut v1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for &c in &corners {
        let (u, v, _) = proj(c);
        u0 = u0.min(u);
        u1 = u1.max(u);
        v0 = v0.min(v);
        v1 = v1.max(v);
    }
    let [l, t, r, b] = fr.area;
    let scale = ((r - l) / (u1 - u0).max(1e-300)).min((b - t) / (v1 - v0).max(1e-300));
    let ss = opts.supersample as usize;
    let (w, h) = (opts.width as usize * ss, opts.height as usize * ss);
    let sf = ss as f64;
    let ox = (l + 0.5 * ((r - l) - scale * (u1 - u0)) - scale * u0) * sf;
    let oy = (b - 0.5 * ((b - t) - scale * (v1 - v0)) + scale * v0) * sf;
    let s = scale * sf;
    let to_px = |p: [f64; 3]| {
        let (u, v, z) = proj(p);
        (ox + s * u, oy - s * v, s * z)
    };

    let keep = |c: &[f64; 3]| match opts.cut {
        Cut::None => true,
        Cut::Half => {
            // Keep what lies beyond the vertical plane through the centre, as seen
            // horizontally from the camera.
            let hx = [eye[0], eye[1], 0.0];
            dot([c[0] - centre[0], c[1] - centre[1], 0.0], hx) <= 0.0
        }
        Cut::Slab { axis, lo, hi } => (lo..=hi).contains(&c[axis.min(2)]),
    };
    let discs: Vec<Disc> = (0..bed.len())
        .filter(|&i| keep(&bed.centres[i].0))
        .map(|i| {
            let (x, y, z) = to_px(bed.centres[i].0);
            Disc {
                x: x as f32,
                y: y as f32,
                depth: z as f32,
                r: (bed.radii[i] * s) as f32,
                id: i as u32,
            }
        })
        .collect();
    let zb = rasterise(&discs, w, h);
    // Discs by particle id, to find a sample's sphere.
    let mut slot = vec![u32::MAX; bed.len()];
    for (k, d) in discs.iter().enumerate() {
        slot[d.id as usize] = k as u32;
    }

    // Light from the upper left, in front; Blinn half vector towards the viewer.
    let light = normalize([-0.45, 0.6, 0.66]);
    let half = normalize([light[0], light[1], light[2] + 1.0]);
    let outline = opts.outlines;
    let mut rgb = vec![0f32; 3 * w * h];
    rgb.par_chunks_mut(3 * w).enumerate().for_each(|(y, row)| {
        for x in 0..w {
            let p = y * w + x;
            let id = zb.id[p];
            let px = &mut row[3 * x..3 * x + 3];
            if id == u32::MAX {
                px.copy_from_slice(&[255.0; 3]);
                continue;
            }
            let d = &discs[slot[id as usize] as usize];
            let mut c = shade(d, x, y, pal.colours[id as usize], light, half);
            if outline {
                // A silhouette: a neighbour sample is background or clearly behind.
                let z = zb.depth[p];
                let gap = 0.15 * d.r;
                let behind =
                    |q: usize| zb.id[q] != id && (zb.id[q] == u32::MAX || zb.depth[q] - z > gap);
                let edge = (x > 0 && behind(p - 1))
                    || (x + 1 < zb.w && behind(p + 1))
                    || (y > 0 && behind(p - w))
                    || (y + 1 < zb.h && behind(p + w));
                if edge {
                    for v in c.iter_mut() {
                        *v *= 0.35;
                    }
                }
            }
            px.copy_from_slice(&c);
        }
    });

    // Box edges, hidden where spheres are in front of them.
    let lw = ((fr.font / 12.0).max(1.0) * sf).round().max(1.0) as i64;
    let edges = [
        (0, 1),
        (2, 3),
        (4, 5),
        (6, 7),
        (0, 2),
        (1, 3),
        (4, 6),
        (5, 7),
        (0, 4),
        (1, 5),
        (2, 6),
        (3, 7),
    ];
    for (a, b) in edges {
        let (pa, pb) = (to_px(corners[a]), to_px(corners[b]));
        let steps = ((pb.0 - pa.0).abs().max((pb.1 - pa.1).abs()).ceil() as usize).max(1);
        for k in 0..=steps {
            let t = k as f64 / steps as f64;
            let (x, y) = (pa.0 + t * (pb.0 - pa.0), pa.1 + t * (pb.1 - pa.1));
            for oy in 0..lw {
                for ox in 0..lw {
                    let (xi, yi) = (
                        x.floor() as i64 + ox - lw / 2,
                        y.floor() as i64 + oy - lw / 2,
                    );
                    if xi < 0 || yi < 0 || xi >= w as i64 || yi >= h as i64 {
                        continue;
                    }
                    let p = yi as usize * w + xi as usize;
                    // Only on empty paper: edges behind spheres are hidden, and
                    // edges in front of them would read as part of the bed.
                    if zb.id[p] == u32::MAX {
                        rgb[3 * p..3 * p + 3].copy_from_slice(&[30.0; 3]);
                    }
                }
            }
        }
    }

    // Average the samples of each pixel into an opaque RGBA image.
    let (ow, oh) = (opts.width as usize, opts.height as usize);
    let mut data = vec![255u8; 4 * ow * oh];
    let norm = 1.0 / (ss * ss) as f32;
    data.par_chunks_mut(4 * ow)
        .enumerate()
        .for_each(|(y, row)| {
            for x in 0..ow {
                let mut acc = [0f32; 3];
                for sy in 0..ss {
                    for sx in 0..ss {
                        let p = (y * ss + sy) * w + x * ss + sx;
                        for k in 0..3 {
                            acc[k] += rgb[3 * p + k];
                        }
                    }
                }
                for k in 0..3 {
                    row[4 * x + k] = (acc[k] * norm).round().clamp(0.0, 255.0) as u8;
                }
            }
        });
    let size_px = tiny_skia::IntSize::from_wh(opts.width, opts.height)
        .ok_or_else(|| Error::Impossible("empty image".into()))?;
    let pixmap = tiny_skia::Pixmap::from_vec(data, size_px)
        .ok_or_else(|| Error::Impossible("image buffer of the wrong size".into()))?;
    let mut canvas = PngCanvas::from_pixmap(pixmap);
    let mut title = opts
        .title
        .clone()
        .unwrap_or_else(|| default_title(bed, opts));
    if opts.title.is_none() {
        match opts.cut {
            Cut::None => {}
            Cut::Half => title.push_str(", back half"),
            Cut::Slab { axis, lo, hi } => {
                let name = ["x", "y", "z"][axis.min(2)];
                title.push_str(&format!(
                    ", slab {} ≤ {name} ≤ {}",
                    super::plot::format_number(lo),
                    super::plot::format_number(hi)
                ));
            }
        }
    }
    frame::draw(
        &mut canvas,
        &fr,
        &title,
        &pal,
        scale,
        " (in the image plane)",
        ox / sf + scale * u0,
    );
    canvas.encode()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn basis_is_orthonormal_and_right_handed() {
        for (a, e) in [(-30.0, 30.0), (0.0, 0.0), (45.0, 90.0), (120.0, -20.0)] {
            let [eye, right, up] = View {
                azimuth: a,
                elevation: e,
            }
            .basis();
            for v in [eye, right, up] {
                assert!((dot(v, v) - 1.0).abs() < 1e-12);
            }
            assert!(dot(eye, right).abs() < 1e-12);
            assert!(dot(eye, up).abs() < 1e-12);
            assert!(dot(right, up).abs() < 1e-12);
            // right × up points towards the camera.
            let c = cross(right, up);
            assert!((dot(c, eye) - 1.0).abs() < 1e-12);
        }
        // From the front: right is +x, up is +z.
        let [_, right, up] = View {
            azimuth: 0.0,
            elevation: 0.0,
        }
        .basis();
        assert!((right[0] - 1.0).abs() < 1e-12 && (up[2] - 1.0).abs() < 1e-12);
    }

    #[test]
    fn zbuffer_keeps_the_nearest_surface_and_breaks_ties_by_id() {
        let discs = [
            Disc {
                x: 20.0,
                y: 20.0,
                depth: 10.0,
                r: 8.0,
                id: 0,
            },
            Disc {
                x: 20.0,
                y: 20.0,
                depth: 5.0,
                r: 4.0,
                id: 1,
            },
            Disc {
                x: 60.0,
                y: 20.0,
                depth: 0.0,
                r: 4.0,
                id: 3,
            },
            Disc {
                x: 60.0,
                y: 20.0,
                depth: 0.0,
                r: 4.0,
                id: 2,
            },
        ];
        let zb = rasterise(&discs, 80, 40);
        let at = |x: usize, y: usize| zb.id[y * 80 + x];
        // Centre: sphere 1's front is at 5 − 4 = 1, sphere 0's at 10 − 8 = 2.
        assert_eq!(at(20, 20), 1);
        assert!((zb.depth[20 * 80 + 20] - (5.0 - (16.0f32 - 0.5).sqrt())).abs() < 1e-5);
        // Off-centre, outside sphere 1's disc: sphere 0.
        assert_eq!(at(26, 20), 0);
        assert_eq!(at(2, 2), u32::MAX);
        // Equal spheres: the lower id wins whatever the order given.
        assert_eq!(at(60, 20), 2);
    }
}
