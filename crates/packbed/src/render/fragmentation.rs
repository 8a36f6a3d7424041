//! Pictures of a bed under load (`docs/reference/fragmentation.md`, "What it writes"):
//! `forces.png`/`.svg`, every bond of the intact bed as a line whose width and
//! colour grow with its force, tension and compression in two colour ramps,
//! with the load arrows; and `breakage.png`/`.svg`, the broken bonds
//! highlighted and numbered in breaking order over the bed, like the source
//! study's force figures.
//!
//! A bond is drawn between the centres of its two beads (a pair across a
//! periodic side: from each bead towards its partner's image, each half cut at
//! the side it crosses), a wall bond from the bead's centre to its contact
//! point. The particles are drawn faintly underneath.
//!
//! 2D beds are drawn in bed coordinates (the SVG holds them exactly, under one
//! transform). 3D beds are drawn as an orthographic **projection** of the whole
//! bed onto the x–z plane, seen from the front (the −y side) with the vertical
//! axis up, and a depth cue: the farther back (larger y) a particle or a bond,
//! the lighter it is drawn, and bonds also thinner; particles are drawn back to
//! front.
//!
//! The pictures reach from the floor to the bed's top (a roof far above a low
//! bed is left out, the box drawn open); arrows get a margin around it.
//!
//! In the SVG, each bond's line is a `<polyline class="bond …">` (the second
//! half of a bond across a periodic side is `class="bond-image"`), each
//! particle a `<circle class="particle">`, each break's number a
//! `<circle class="break-label">` followed by its `<text>`.

use super::bed2d::world_to_pixel;
use super::canvas::{
    cap_height, text_width, Anchor, Canvas, PngCanvas, Rgb, Style, SvgCanvas, TextStyle,
    WorldToPixel,
};
use super::colour;
use super::frame::{self, Frame};
use super::plot::{format_number, format_tick};
use super::Palette;
use crate::bed::Bed;
use crate::error::{Error, Result};
use crate::math::{Real, Vector};
use crate::mechanics::Fragmentation;

/// Width of the pictures in pixels.
pub const WIDTH: u32 = 1200;
/// Height of the pictures in pixels.
pub const HEIGHT: u32 = 1000;

/// The pictures of `frag` (a fragmentation of `bed`), in this order:
/// `forces.png`, `forces.svg`, `breakage.png`, `breakage.svg`, each as its
/// file name and bytes ([`WIDTH`] × [`HEIGHT`] pixels).
pub fn fragmentation_pictures<const D: usize>(
    bed: &Bed<D>,
    frag: &Fragmentation<D>,
) -> Result<Vec<(String, Vec<u8>)>> {
    check(bed, frag)?;
    type Draw<const D: usize> = fn(&mut dyn Canvas, &Bed<D>, &Fragmentation<D>) -> Result<()>;
    let pictures: [(&str, Draw<D>); 2] = [("forces", draw_forces), ("breakage", draw_breakage)];
    let mut out = Vec::with_capacity(4);
    for (name, draw) in pictures {
        let mut png = PngCanvas::new(WIDTH, HEIGHT)?;
        draw(&mut png, bed, frag)?;
        out.push((format!("{name}.png"), png.encode()?));
        let mut svg = SvgCanvas::new(WIDTH, HEIGHT);
        draw(&mut svg, bed, frag)?;
        out.push((format!("{name}.svg"), svg.finish().into_bytes()));
    }
    Ok(out)
}

/// The largest force `|f|` among the bonds of each particle's body in the
/// intact bed (0 for a body without bonds), in particle order.
pub fn particle_forces<const D: usize>(bed: &Bed<D>, frag: &Fragmentation<D>) -> Vec<Real> {
    let mut body = vec![0.0 as Real; frag.bodies.len()];
    for (g, f) in frag.bonds.iter().zip(&frag.forces) {
        let m = f.norm();
        if !m.is_finite() {
            continue;
        }
        for b in std::iter::once(g.i).chain(g.j) {
            if let Some(v) = body.get_mut(b as usize) {
                *v = Real::max(*v, m);
            }
        }
    }
    (0..bed.len())
        .map(|k| {
            frag.bodies
                .of_particle
                .get(k)
                .and_then(|&b| body.get(b as usize))
                .copied()
                .unwrap_or(0.0)
        })
        .collect()
}

/// Refuses a fragmentation that is not of this bed (or a bed that cannot be drawn).
fn check<const D: usize>(bed: &Bed<D>, frag: &Fragmentation<D>) -> Result<()> {
    if D != 2 && D != 3 {
        return Err(Error::Impossible(format!("{D}D beds cannot be drawn")));
    }
    let n = bed.len();
    let nb = frag.bodies.len();
    let bead_ok = |b: u32| (b as usize) < n;
    let body_ok = |b: u32| (b as usize) < nb;
    let fits = frag.bodies.of_particle.len() == n
        && frag.forces.len() == frag.bonds.len()
        && frag.bonds.iter().all(|g| {
            bead_ok(g.bead_i)
                && g.bead_j.is_none_or(bead_ok)
                && body_ok(g.i)
                && g.j.is_none_or(body_ok)
        })
        && frag.steps.iter().all(|s| s.bond < frag.bonds.len())
        && frag.loads.iter().all(|l| body_ok(l.body));
    if !fits {
        return Err(Error::Impossible(format!(
            "the fragmentation ({} bonds over {nb} bodies) is not of this bed of {n} particles",
            frag.bonds.len()
        )));
    }
    Ok(())
}

/// Where the bed goes in the picture, and how big things are drawn.
struct Scene<'a, const D: usize> {
    bed: &'a Bed<D>,
    frame: Frame,
    world: WorldToPixel,
    /// Room left around the box for the load arrows (bed units).
    margin: f64,
}

/// One row of a legend.
enum Row {
    /// Plain text (a heading).
    Text(String),
    /// A line sample of this colour and width, and its label.
    Line(Rgb, f64, String),
    /// A load arrow sample, and its label.
    Arrow(Rgb, f64, String),
    /// A break number's badge sample, and its label.
    Badge(String),
}

impl Row {
    fn label(&self) -> &str {
        match self {
            Row::Text(t) | Row::Line(_, _, t) | Row::Arrow(_, _, t) | Row::Badge(t) => t,
        }
    }
}

/// Colour of the load arrows: dark bluish green (neither ramp's hue).
const LOAD: Rgb = Rgb(0, 120, 86);
/// Colour of the intact bonds in the breakage picture.
const INTACT: Rgb = Rgb(140, 140, 140);

impl<'a, const D: usize> Scene<'a, D> {
    /// Lays out a `width × height` picture with a legend of `rows`.
    fn new(bed: &'a Bed<D>, width: u32, height: u32, rows: &[Row]) -> Self {
        // The frame sizes its legend column from the labels; the line samples
        // are wider than its swatches, so the column gets a little more.
        let pal = Palette {
            colours: Vec::new(),
            legend: rows
                .iter()
                .map(|r| (Rgb::BLACK, r.label().to_string()))
                .collect(),
            heading: String::new(),
        };
        let mut fr = frame::layout(width, height, &pal);
        let extra = 1.2 * fr.font;
        fr.area[2] = (fr.area[2] - extra).max(fr.area[0] + 10.0);
        fr.legend_x = (fr.legend_x - extra).max(fr.area[2]);
        let (w, h) = extent(bed);
        let margin = 0.06 * w.max(h);
        let mut world = world_to_pixel(&fr, w + 2.0 * margin, h + 2.0 * margin);
        world.tx += margin * world.scale;
        world.ty -= margin * world.scale;
        Scene {
            bed,
            frame: fr,
            world,
            margin,
        }
    }

    /// A point of the bed in the picture plane (bed units): x and the vertical.
    fn at(&self, p: &Vector<D>) -> (f64, f64) {
        (p[0], p[D - 1])
    }

    /// How far back a point lies: 0 at the front (y = 0), 1 at the back (3D);
    /// always 0 in 2D.
    fn depth(&self, p: &Vector<D>) -> f64 {
        if D == 3 {
            let y = self.bed.container.size[1];
            let t = if y > 0.0 { p[1] / y } else { 0.0 };
            if t.is_finite() {
                t.clamp(0.0, 1.0)
            } else {
                0.0
            }
        } else {
            0.0
        }
    }

    /// Mean particle radius in pixels.
    fn radius_px(&self) -> f64 {
        let n = self.bed.len().max(1) as f64;
        let mean = self.bed.radii.iter().sum::<Real>() / n;
        finite_or(mean * self.world.scale, 1.0)
    }

    /// Width of the load arrows in pixels.
    fn load_width(&self) -> f64 {
        (0.22 * self.radius_px()).clamp(1.5, 4.0)
    }

    /// The particles, faint, back to front.
    fn particles(&self, canvas: &mut dyn Canvas) {
        let bed = self.bed;
        let mut order: Vec<usize> = (0..bed.len()).collect();
        let depth: Vec<f64> = bed.centres.iter().map(|c| self.depth(c)).collect();
        order.sort_by(|&a, &b| depth[b].total_cmp(&depth[a]).then(a.cmp(&b)));
        let outline = bed.r_min() * self.world.scale >= 2.5;
        for k in order {
            let (x, y) = self.at(&bed.centres[k]);
            let r = bed.radii[k];
            if !(x.is_finite() && y.is_finite() && r.is_finite()) {
                continue;
            }
            let fade = 0.65 * depth[k];
            let style = Style {
                fill: Some(Rgb(222, 222, 222).mix(Rgb::WHITE, fade)),
                stroke: outline.then(|| (Rgb(175, 175, 175).mix(Rgb::WHITE, fade), 0.6)),
            };
            canvas.circle(x, y, r, style, "particle");
        }
    }

    /// The box outline: floor and sides up to the picture's top, and the roof
    /// if it is in the picture.
    fn container(&self, canvas: &mut dyn Canvas) {
        let size = self.bed.container.size;
        let lw = (self.frame.font / 10.0).max(1.5);
        let (w, h) = extent(self.bed);
        let roof = size[D - 1];
        if roof <= h {
            canvas.rect(0.0, 0.0, w, roof, Style::stroke(Rgb::BLACK, lw));
        } else {
            canvas.polyline_class(
                &[(0.0, h), (0.0, 0.0), (w, 0.0), (w, h)],
                Rgb::BLACK,
                lw,
                "box",
            );
        }
    }

    /// Bond `k` as drawn: its pieces in the picture plane (bed units) and how
    /// far back it lies.
    fn bond(&self, frag: &Fragmentation<D>, k: usize) -> Drawn {
        let g = &frag.bonds[k];
        let c = &self.bed.container;
        let a = self.bed.centres[g.bead_i as usize];
        let pa = self.at(&a);
        match g.bead_j {
            None => Drawn {
                main: [pa, self.at(&g.point)],
                image: None,
                depth: self.depth(&a),
            },
            Some(b) => {
                let b = self.bed.centres[b as usize];
                let d = c.displacement(&a, &b);
                let end = a + d;
                let depth = self.depth(&c.wrap(a + d * 0.5));
                let w = c.size[0];
                // Across a periodic side in x, each half is cut at the side.
                // (Across the y sides of a 3D box the projection needs no cut:
                // the partner's image projects onto the partner.)
                if c.periodic && (end[0] - b[0]).abs() > 1e-9 * w {
                    let start = self.at(&b);
                    let back = self.at(&(b - d));
                    Drawn {
                        main: [pa, clip_x(pa, self.at(&end), w)],
                        image: Some([start, clip_x(start, back, w)]),
                        depth,
                    }
                } else {
                    Drawn {
                        main: [pa, self.at(&end)],
                        image: None,
                        depth,
                    }
                }
            }
        }
    }

    /// Draws a bond's pieces.
    fn stroke(&self, canvas: &mut dyn Canvas, d: &Drawn, colour: Rgb, width: f64, class: &str) {
        if !(finite2(d.main[0]) && finite2(d.main[1]) && width.is_finite()) {
            return;
        }
        canvas.polyline_class(&d.main, colour, width, class);
        if let Some(im) = d.image {
            if finite2(im[0]) && finite2(im[1]) {
                canvas.polyline_class(&im, colour, width, "bond-image");
            }
        }
    }

    /// The load arrows: each ends at its load's point, pointing along the
    /// load's force (in the picture plane), its length proportional to its
    /// share of the total.
    fn loads(&self, canvas: &mut dyn Canvas, frag: &Fragmentation<D>) {
        let largest = frag
            .loads
            .iter()
            .map(|l| l.force.norm())
            .filter(|m| m.is_finite())
            .fold(0.0, Real::max);
        if largest <= 0.0 {
            return;
        }
        let s = self.world.scale;
        let lw = self.load_width();
        for l in &frag.loads {
            let (fx, fz) = self.at(&l.force);
            let m = fx.hypot(fz);
            let share = l.force.norm() / largest;
            if !(m > 1e-12 * largest && share.is_finite()) {
                continue;
            }
            let (ux, uz) = (fx / m, fz / m);
            let len = 0.9 * self.margin * share;
            let tip = self.at(&l.point);
            let tail = (tip.0 - ux * len, tip.1 - uz * len);
            if !(finite2(tip) && finite2(tail)) {
                continue;
            }
            canvas.polyline_class(&[tail, tip], LOAD, lw, "load");
            // The head: two barbs, at most 40 % of the arrow.
            let h = (0.4 * len).min(4.0 * lw / s);
            let barb = |a: f64| {
                let (c, sn) = (a.cos(), a.sin());
                (
                    tip.0 - h * (c * ux - sn * uz),
                    tip.1 - h * (sn * ux + c * uz),
                )
            };
            canvas.polyline_class(&[barb(0.45), tip, barb(-0.45)], LOAD, lw, "load-head");
        }
    }

    /// Title, scale bar and the legend `rows` around the picture.
    fn furnish(&self, canvas: &mut dyn Canvas, title: &str, rows: &[Row]) {
        let empty = Palette {
            colours: Vec::new(),
            legend: Vec::new(),
            heading: String::new(),
        };
        let note = if D == 3 { " (x–z projection)" } else { "" };
        frame::draw(
            canvas,
            &self.frame,
            title,
            &empty,
            self.world.scale,
            note,
            self.world.tx,
        );
        legend(canvas, &self.frame, rows);
    }
}

/// A bond as drawn.
struct Drawn {
    /// From bead i's centre.
    main: [(f64, f64); 2],
    /// From bead j's centre, for a bond across a periodic side.
    image: Option<[(f64, f64); 2]>,
    /// 0 at the front, 1 at the back.
    depth: f64,
}

/// Width and height of the picture plane (bed units): the box's width, and
/// the bed's top (the box's height if the bed is empty). A roof far above a
/// low bed would only shrink it.
fn extent<const D: usize>(bed: &Bed<D>) -> (f64, f64) {
    let size = bed.container.size;
    let top = bed.top();
    let h = if top > 0.0 { top } else { size[D - 1] };
    (
        finite_or(size[0], 1.0).max(f64::MIN_POSITIVE),
        finite_or(h, 1.0).max(f64::MIN_POSITIVE),
    )
}

fn finite_or(v: f64, default: f64) -> f64 {
    if v.is_finite() {
        v
    } else {
        default
    }
}

fn finite2(p: (f64, f64)) -> bool {
    p.0.is_finite() && p.1.is_finite()
}

/// The segment `p → q` cut where it leaves `0 ≤ x ≤ w` (`p` inside).
fn clip_x(p: (f64, f64), q: (f64, f64), w: f64) -> (f64, f64) {
    let dx = q.0 - p.0;
    let t = if q.0 > w && dx > 0.0 {
        (w - p.0) / dx
    } else if q.0 < 0.0 && dx < 0.0 {
        -p.0 / dx
    } else {
        1.0
    };
    let t = finite_or(t, 1.0).clamp(0.0, 1.0);
    (p.0 + t * dx, p.1 + t * (q.1 - p.1))
}

/// Draws the legend `rows` in the frame's legend column.
fn legend(canvas: &mut dyn Canvas, fr: &Frame, rows: &[Row]) {
    let f = fr.font;
    let (w, _) = canvas.size();
    let sample = 2.2 * f;
    let gap = 0.6 * f;
    let widest = rows
        .iter()
        .map(|r| {
            let t = text_width(r.label(), f);
            match r {
                Row::Text(_) => t,
                _ => t + sample + gap,
            }
        })
        .fold(0.0, f64::max);
    let avail = w as f64 - fr.legend_x - 0.5 * f;
    let size = if widest > avail && widest > 0.0 {
        f * avail / widest
    } else {
        f
    };
    let (sample, gap) = (sample * size / f, gap * size / f);
    let row_h = (1.6 * size).min((fr.area[3] - fr.area[1]) / rows.len().max(1) as f64);
    let x = fr.legend_x;
    let mut y = fr.area[1] + cap_height(size);
    for r in rows {
        let mid = y - cap_height(size) / 2.0;
        match r {
            Row::Text(t) => {
                canvas.text(x, y, t, TextStyle::new(size, Anchor::Start));
            }
            Row::Line(c, lw, t) => {
                canvas.polyline_class(&[(x, mid), (x + sample, mid)], *c, *lw, "legend");
                canvas.text(x + sample + gap, y, t, TextStyle::new(size, Anchor::Start));
            }
            Row::Arrow(c, lw, t) => {
                let tip = (x + sample, mid);
                let h = (0.4 * sample).min(4.0 * lw);
                canvas.polyline_class(&[(x, mid), tip], *c, *lw, "legend");
                canvas.polyline_class(
                    &[
                        (tip.0 - h * 0.45f64.cos(), mid - h * 0.45f64.sin()),
                        tip,
                        (tip.0 - h * 0.45f64.cos(), mid + h * 0.45f64.sin()),
                    ],
                    *c,
                    *lw,
                    "legend",
                );
                canvas.text(x + sample + gap, y, t, TextStyle::new(size, Anchor::Start));
            }
            Row::Badge(t) => {
                badge(canvas, x + 0.5 * sample, mid, "1", size, "legend");
                canvas.text(x + sample + gap, y, t, TextStyle::new(size, Anchor::Start));
            }
        }
        y += row_h;
    }
}

/// A number in a white disc ringed in the highlight colour, centred at pixel
/// `(x, y)`.
fn badge(canvas: &mut dyn Canvas, x: f64, y: f64, text: &str, size: f64, class: &str) {
    let r = (0.62 * size).max(0.5 * text_width(text, size) + 0.25 * size);
    canvas.circle(
        x,
        y,
        r,
        Style::both(Rgb::WHITE, colour::HIGHLIGHT, (0.12 * size).max(1.0)),
        class,
    );
    canvas.text(
        x,
        y + cap_height(size) / 2.0,
        text,
        TextStyle::new(size, Anchor::Middle),
    );
}

/// Rows that explain the 3D projection's depth cue.
fn depth_rows<const D: usize>() -> Vec<Row> {
    if D == 3 {
        vec![
            Row::Text("seen from the front (x–z)".into()),
            Row::Text("farther back: lighter, thinner".into()),
        ]
    } else {
        Vec::new()
    }
}

/// The forces picture of `frag` (a fragmentation of `bed`) on any canvas.
pub fn draw_forces<const D: usize>(
    canvas: &mut dyn Canvas,
    bed: &Bed<D>,
    frag: &Fragmentation<D>,
) -> Result<()> {
    check(bed, frag)?;
    let magnitude: Vec<f64> = frag
        .forces
        .iter()
        .map(|f| finite_or(f.norm(), 0.0))
        .collect();
    let largest = magnitude.iter().copied().fold(0.0, f64::max);
    let fmax = if largest > 0.0 { largest } else { 1.0 };
    // Width and colour grow with sqrt(|f| / largest): bond forces are broad
    // (a few levers carry several times the load), and a linear scale would
    // leave all but those few invisible.
    let scale = |m: f64| (m / fmax).clamp(0.0, 1.0).sqrt();
    // The legend's samples: |f| = 1, 0.3 and 0.1 × the largest.
    let levels = [1.0, 0.3, 0.1].map(|a: f64| scale(a * fmax));
    let tick = |t: f64| format_tick(t * t * largest, largest / 10.0);
    // The legend's samples take the widths the scale gives, and the scale
    // depends on the legend's labels: lay out with the labels first.
    let rows_with = |line: &dyn Fn(f64) -> f64, arrow: f64| {
        let mut rows = vec![Row::Text(format!(
            "bond force |f| (total load {})",
            format_number(crate::mechanics::TOTAL)
        ))];
        rows.push(Row::Text("tension".into()));
        for t in levels {
            rows.push(Row::Line(colour::tension(t), line(t), tick(t)));
        }
        rows.push(Row::Text("compression".into()));
        for t in levels {
            rows.push(Row::Line(colour::compression(t), line(t), tick(t)));
        }
        rows.push(Row::Arrow(LOAD, arrow, "load (length ∝ share)".into()));
        rows.extend(depth_rows::<D>());
        rows
    };
    let (w, h) = canvas.size();
    let scene = Scene::new(bed, w, h, &rows_with(&|_| 1.0, 1.0));
    let wmax = (0.5 * scene.radius_px()).clamp(1.5, 12.0);
    let wmin = (0.08 * wmax).max(0.35);
    let width = |t: f64| wmin + (wmax - wmin) * t;
    let rows = rows_with(&width, scene.load_width());

    canvas.set_world(Some(scene.world));
    scene.particles(canvas);
    let drawn: Vec<Drawn> = (0..frag.bonds.len()).map(|k| scene.bond(frag, k)).collect();
    // Weak bonds first, so the strong ones lie on top.
    let weight: Vec<f64> = (0..frag.bonds.len())
        .map(|k| scale(magnitude[k]) * (1.0 - 0.5 * drawn[k].depth))
        .collect();
    let mut order: Vec<usize> = (0..frag.bonds.len()).collect();
    order.sort_by(|&a, &b| weight[a].total_cmp(&weight[b]).then(a.cmp(&b)));
    for k in order {
        let t = scale(magnitude[k]);
        let tension = frag.normal(k) > 0.0;
        let (c, class) = if tension {
            (colour::tension(t), "bond tension")
        } else {
            (colour::compression(t), "bond compression")
        };
        let d = &drawn[k];
        let c = c.mix(Rgb::WHITE, 0.7 * d.depth);
        let w = width(t) * (1.0 - 0.5 * d.depth);
        scene.stroke(canvas, d, c, w, class);
    }
    scene.container(canvas);
    scene.loads(canvas, frag);
    canvas.set_world(None);

    let title = format!(
        "Bond forces under {}: {}, {} bonds",
        frag.summary.load.name(),
        bed.describe(),
        frag.bonds.len()
    );
    scene.furnish(canvas, &title, &rows);
    Ok(())
}

/// Breaks numbered in the breakage picture; past this many, numbers would
/// pile up over each other, so the rest show their order by colour.
pub const NUMBERED_BREAKS: usize = 20;

/// Where along viridis the last break lies: its yellow end vanishes on the
/// pale particles.
const ORDER_TOP: f64 = 0.88;

/// The colour of break `k` (from 0) of `n` when breaks are coloured by order.
fn order_colour(k: usize, n: usize) -> Rgb {
    let t = if n > 1 {
        k as f64 / (n - 1) as f64
    } else {
        0.0
    };
    colour::viridis(ORDER_TOP * t)
}

/// The breakage picture of `frag` (a fragmentation of `bed`) on any canvas:
/// broken bonds highlighted and the first [`NUMBERED_BREAKS`] numbered; with
/// more breaks than that, every broken bond is coloured by its order, with a
/// colour scale in the legend.
pub fn draw_breakage<const D: usize>(
    canvas: &mut dyn Canvas,
    bed: &Bed<D>,
    frag: &Fragmentation<D>,
) -> Result<()> {
    check(bed, frag)?;
    let n = frag.steps.len();
    let by_order = n > NUMBERED_BREAKS;
    let mut rows = vec![
        Row::Text("bonds".into()),
        Row::Line(INTACT, 1.0, "intact".into()),
    ];
    if by_order {
        rows.push(Row::Text("broken, by breaking order".into()));
        // Five samples of the scale, first break at the top.
        let mut picks: Vec<usize> = (0..5).map(|q| q * (n - 1) / 4).collect();
        picks.dedup();
        for k in picks {
            let c = order_colour(k, n);
            rows.push(Row::Line(c, 1.0, format!("break {}", frag.steps[k].step)));
        }
        rows.push(Row::Badge(format!("first {NUMBERED_BREAKS} numbered")));
    } else {
        rows.push(Row::Line(colour::HIGHLIGHT, 1.0, "broken".into()));
        rows.push(Row::Badge("breaking order".into()));
    }
    rows.extend(depth_rows::<D>());
    let (w, h) = canvas.size();
    let scene = Scene::new(bed, w, h, &rows);
    let r_px = scene.radius_px();
    let thin = (0.08 * r_px).clamp(0.6, 1.5);
    let thick = (0.45 * r_px).clamp(2.0, 8.0);
    // Many coloured breaks are drawn thinner, so that they do not hide
    // each other's colours.
    let broken_w = if by_order {
        thick.min((0.25 * r_px).max(1.5))
    } else {
        thick
    };
    for (k, r) in rows.iter_mut().enumerate() {
        if let Row::Line(_, w, _) = r {
            *w = if k == 1 { thin } else { broken_w };
        }
    }

    let mut broken = vec![false; frag.bonds.len()];
    for s in &frag.steps {
        broken[s.bond] = true;
    }
    canvas.set_world(Some(scene.world));
    scene.particles(canvas);
    // Intact bonds, back to front, then the broken ones on top.
    let drawn: Vec<Drawn> = (0..frag.bonds.len()).map(|k| scene.bond(frag, k)).collect();
    let mut order: Vec<usize> = (0..frag.bonds.len()).filter(|&k| !broken[k]).collect();
    order.sort_by(|&a, &b| drawn[b].depth.total_cmp(&drawn[a].depth).then(a.cmp(&b)));
    for k in order {
        let d = &drawn[k];
        let c = INTACT.mix(Rgb::WHITE, 0.6 * d.depth);
        scene.stroke(canvas, d, c, thin * (1.0 - 0.5 * d.depth), "bond intact");
    }
    if by_order {
        // The last break at the bottom, so the numbered first ones lie on top.
        let width = broken_w;
        for (k, s) in frag.steps.iter().enumerate().rev() {
            let d = &drawn[s.bond];
            let c = order_colour(k, n).mix(Rgb::WHITE, 0.45 * d.depth);
            scene.stroke(canvas, d, c, width * (1.0 - 0.4 * d.depth), "bond broken");
        }
    } else {
        for s in &frag.steps {
            let d = &drawn[s.bond];
            let c = colour::HIGHLIGHT.mix(Rgb::WHITE, 0.45 * d.depth);
            scene.stroke(canvas, d, c, thick * (1.0 - 0.4 * d.depth), "bond broken");
        }
    }
    scene.container(canvas);
    canvas.set_world(None);

    // The numbers, in pixels: the first break on top.
    let size = (1.2 * r_px).min(0.8 * scene.frame.font).max(8.0);
    for s in frag.steps.iter().take(NUMBERED_BREAKS).rev() {
        let (x, y) = scene.at(&frag.bonds[s.bond].point);
        let (px, py) = scene.world.apply(x, y);
        if finite2((px, py)) {
            badge(canvas, px, py, &s.step.to_string(), size, "break-label");
        }
    }

    let sm = &frag.summary;
    let end = match sm.breaks_to_failure {
        Some(k) => format!("failed at break {k}"),
        None => "stopped before failure".into(),
    };
    let title = format!(
        "Breakage under {}: {}, {} of {} bonds broken, {end}",
        sm.load.name(),
        bed.describe(),
        frag.steps.len(),
        frag.bonds.len()
    );
    scene.furnish(canvas, &title, &rows);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clipping_stops_at_the_sides() {
        assert_eq!(clip_x((1.0, 0.0), (3.0, 2.0), 10.0), (3.0, 2.0));
        assert_eq!(clip_x((9.0, 0.0), (11.0, 2.0), 10.0), (10.0, 1.0));
        assert_eq!(clip_x((1.0, 0.0), (-1.0, 4.0), 10.0), (0.0, 2.0));
        // A point on the side stays put.
        assert_eq!(clip_x((10.0, 5.0), (12.0, 5.0), 10.0), (10.0, 5.0));
    }
}
