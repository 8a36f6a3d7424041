//! One drawing surface, two back ends: SVG text written by hand and PNG pixels
//! rasterised by tiny-skia. Plots, legends and 2D beds are drawn once against
//! [`Canvas`], so both formats show the same picture.
//!
//! Text uses DejaVu Sans embedded in the binary (crate `dejavu`), laid out and
//! rasterised with `ab_glyph`: pictures look the same on a cluster node with no
//! fonts installed, and the same metrics size the margins of both formats, so no
//! label is clipped. The SVG names the font family first, with fallbacks.

use crate::error::{Error, Result};
use ab_glyph::{Font, FontRef, PxScale, ScaleFont};
use std::fmt::Write as _;
use std::sync::OnceLock;
use tiny_skia::{FillRule, Paint, PathBuilder, Pixmap, Rect, Stroke, Transform};

/// An sRGB colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rgb(pub u8, pub u8, pub u8);

impl Rgb {
    /// Black.
    pub const BLACK: Rgb = Rgb(0, 0, 0);
    /// White.
    pub const WHITE: Rgb = Rgb(255, 255, 255);
    /// Dark grey for outlines and text that should not shout.
    pub const DARK: Rgb = Rgb(40, 40, 40);
    /// Mid grey for grid lines and light outlines.
    pub const GREY: Rgb = Rgb(160, 160, 160);

    /// `#rrggbb`.
    pub fn hex(&self) -> String {
        format!("#{:02x}{:02x}{:02x}", self.0, self.1, self.2)
    }

    /// Linear mix: `t = 0` gives `self`, `t = 1` gives `other`.
    pub fn mix(&self, other: Rgb, t: f64) -> Rgb {
        let m = |a: u8, b: u8| {
            (a as f64 + (b as f64 - a as f64) * t)
                .round()
                .clamp(0.0, 255.0) as u8
        };
        Rgb(m(self.0, other.0), m(self.1, other.1), m(self.2, other.2))
    }
}

/// Fill and outline of a shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Style {
    /// Fill colour, if filled.
    pub fill: Option<Rgb>,
    /// Outline colour and width in pixels, if outlined.
    pub stroke: Option<(Rgb, f64)>,
}

impl Style {
    /// Filled, no outline.
    pub fn fill(c: Rgb) -> Style {
        Style {
            fill: Some(c),
            stroke: None,
        }
    }
    /// Outline only.
    pub fn stroke(c: Rgb, width: f64) -> Style {
        Style {
            fill: None,
            stroke: Some((c, width)),
        }
    }
    /// Filled and outlined.
    pub fn both(fill: Rgb, stroke: Rgb, width: f64) -> Style {
        Style {
            fill: Some(fill),
            stroke: Some((stroke, width)),
        }
    }
}

/// Where a text's anchor point lies along the text.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Anchor {
    /// The anchor is the start of the text.
    Start,
    /// The anchor is the middle of the text.
    Middle,
    /// The anchor is the end of the text.
    End,
}

/// How a line of text is set: its size, its anchor, its direction and colour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextStyle {
    /// Font size in pixels.
    pub size: f64,
    /// Where the anchor point lies along the text.
    pub anchor: Anchor,
    /// Reads bottom to top (a y-axis label).
    pub vertical: bool,
    /// Colour of the glyphs.
    pub color: Rgb,
}

impl TextStyle {
    /// Black horizontal text of `size` pixels anchored at `anchor`.
    pub fn new(size: f64, anchor: Anchor) -> TextStyle {
        TextStyle {
            size,
            anchor,
            vertical: false,
            color: Rgb::BLACK,
        }
    }

    /// The same, reading bottom to top.
    pub fn vertical(self) -> TextStyle {
        TextStyle {
            vertical: true,
            ..self
        }
    }
}

/// Maps bed ("world") coordinates to pixels: `px = tx + s·x`, `py = ty − s·y`
/// (the bed's vertical axis points up, the image's down).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WorldToPixel {
    /// Pixels per length unit.
    pub scale: f64,
    /// Pixel x of world x = 0.
    pub tx: f64,
    /// Pixel y of world y = 0.
    pub ty: f64,
}

impl WorldToPixel {
    /// The pixel position of a world point.
    pub fn apply(&self, x: f64, y: f64) -> (f64, f64) {
        (self.tx + self.scale * x, self.ty - self.scale * y)
    }
}

/// A drawing surface in pixel coordinates (origin top left, y down), with an
/// optional world transform for shapes given in bed coordinates.
pub trait Canvas {
    /// Width and height in pixels.
    fn size(&self) -> (u32, u32);
    /// Sets (or clears) the transform applied to the coordinates of the shapes
    /// that follow; widths of outlines stay in pixels.
    fn set_world(&mut self, world: Option<WorldToPixel>);
    /// An axis-aligned rectangle (corner `x, y`, size `w × h`).
    fn rect(&mut self, x: f64, y: f64, w: f64, h: f64, style: Style);
    /// A circle; `class` names it in SVG (tests and scripts find particles by it).
    fn circle(&mut self, cx: f64, cy: f64, r: f64, style: Style, class: &str);
    /// An open polyline.
    fn polyline(&mut self, points: &[(f64, f64)], color: Rgb, width: f64);
    /// An open polyline that SVG names by `class` (tests and scripts find bonds
    /// by it); the same as [`Canvas::polyline`] elsewhere.
    fn polyline_class(&mut self, points: &[(f64, f64)], color: Rgb, width: f64, _class: &str) {
        self.polyline(points, color, width);
    }
    /// A closed polygon (a band between two curves).
    fn polygon(&mut self, points: &[(f64, f64)], style: Style);
    /// One line of text; `(x, y)` is the anchor on the baseline.
    fn text(&mut self, x: f64, y: f64, text: &str, style: TextStyle);

    /// A straight segment.
    fn line(&mut self, x0: f64, y0: f64, x1: f64, y1: f64, color: Rgb, width: f64) {
        self.polyline(&[(x0, y0), (x1, y1)], color, width);
    }
}

/// The embedded font (DejaVu Sans).
fn font() -> &'static FontRef<'static> {
    static FONT: OnceLock<FontRef<'static>> = OnceLock::new();
    FONT.get_or_init(|| {
        FontRef::try_from_slice(dejavu::sans::regular())
            .expect("the embedded DejaVu Sans is a valid TrueType font")
    })
}

/// Width in pixels of `text` set at `size` pixels (same metrics for SVG and PNG).
pub fn text_width(text: &str, size: f64) -> f64 {
    let f = font();
    let scaled = f.as_scaled(PxScale::from(size as f32));
    let mut w = 0.0f32;
    let mut prev = None;
    for ch in text.chars() {
        let id = f.glyph_id(ch);
        if let Some(p) = prev {
            w += scaled.kern(p, id);
        }
        w += scaled.h_advance(id);
        prev = Some(id);
    }
    w as f64
}

/// Height above the baseline of capital letters at `size` pixels.
pub fn cap_height(size: f64) -> f64 {
    0.73 * size
}

/// An SVG document being written.
pub struct SvgCanvas {
    width: u32,
    height: u32,
    body: String,
    world: Option<WorldToPixel>,
}

impl SvgCanvas {
    /// A white page of `width × height` pixels.
    pub fn new(width: u32, height: u32) -> SvgCanvas {
        let mut body = String::new();
        let _ = writeln!(
            body,
            r#"<rect x="0" y="0" width="{width}" height="{height}" fill="{}"/>"#,
            Rgb::WHITE.hex()
        );
        SvgCanvas {
            width,
            height,
            body,
            world: None,
        }
    }

    /// The finished document.
    pub fn finish(mut self) -> String {
        self.set_world(None);
        format!(
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n\
             <svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" \
             viewBox=\"0 0 {w} {h}\" font-family=\"DejaVu Sans, Verdana, Arial, sans-serif\">\n{}</svg>\n",
            self.body,
            w = self.width,
            h = self.height
        )
    }

    /// The `points` attribute's value of a polyline or polygon.
    fn points_value(&self, points: &[(f64, f64)]) -> String {
        let wd = self.world.is_some();
        let pts: Vec<String> = points
            .iter()
            .map(|&(x, y)| format!("{},{}", fmt_coord(x, wd), fmt_coord(y, wd)))
            .collect();
        pts.join(" ")
    }

    /// A `<polyline>` with extra attributes `attrs` (empty, or starting with a space).
    fn write_polyline(&mut self, points: &[(f64, f64)], color: Rgb, width: f64, attrs: &str) {
        let _ = writeln!(
            self.body,
            r#"<polyline{attrs} points="{}"{} stroke-linejoin="round"/>"#,
            self.points_value(points),
            self.style_attrs(Style::stroke(color, width))
        );
    }

    fn style_attrs(&self, style: Style) -> String {
        let mut s = String::new();
        match style.fill {
            Some(c) => {
                let _ = write!(s, r#" fill="{}""#, c.hex());
            }
            None => s.push_str(r#" fill="none""#),
        }
        if let Some((c, w)) = style.stroke {
            let _ = write!(s, r#" stroke="{}" stroke-width="{}""#, c.hex(), fmt_px(w));
            if self.world.is_some() {
                s.push_str(r#" vector-effect="non-scaling-stroke""#);
            }
        }
        s
    }
}

/// Pixel quantities to 0.01 px: smaller files, no visible difference.
fn fmt_px(v: f64) -> String {
    let r = (v * 100.0).round() / 100.0;
    format!("{r}")
}

/// A coordinate: in world space written exactly (shortest round-trip form), so a
/// script can read particle positions back from the SVG; in pixels to 0.01.
fn fmt_coord(v: f64, world: bool) -> String {
    if world {
        format!("{v}")
    } else {
        fmt_px(v)
    }
}

impl Canvas for SvgCanvas {
    fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    fn set_world(&mut self, world: Option<WorldToPixel>) {
        if self.world.is_some() {
            self.body.push_str("</g>\n");
        }
        if let Some(w) = world {
            let _ = writeln!(
                self.body,
                r#"<g transform="matrix({} 0 0 {} {} {})">"#,
                w.scale, -w.scale, w.tx, w.ty
            );
        }
        self.world = world;
    }

    fn rect(&mut self, x: f64, y: f64, w: f64, h: f64, style: Style) {
        let wd = self.world.is_some();
        // In world space (y up) the corner given is the lower left one; SVG
        // wants non-negative sizes, which the flipped transform keeps correct.
        let _ = writeln!(
            self.body,
            r#"<rect x="{}" y="{}" width="{}" height="{}"{}/>"#,
            fmt_coord(x, wd),
            fmt_coord(y, wd),
            fmt_coord(w, wd),
            fmt_coord(h, wd),
            self.style_attrs(style)
        );
    }

    fn circle(&mut self, cx: f64, cy: f64, r: f64, style: Style, class: &str) {
        let wd = self.world.is_some();
        let _ = writeln!(
            self.body,
            r#"<circle class="{class}" cx="{}" cy="{}" r="{}"{}/>"#,
            fmt_coord(cx, wd),
            fmt_coord(cy, wd),
            fmt_coord(r, wd),
            self.style_attrs(style)
        );
    }

    fn polyline(&mut self, points: &[(f64, f64)], color: Rgb, width: f64) {
        self.write_polyline(points, color, width, "");
    }

    fn polygon(&mut self, points: &[(f64, f64)], style: Style) {
        let _ = writeln!(
            self.body,
            r#"<polygon points="{}"{}/>"#,
            self.points_value(points),
            self.style_attrs(style)
        );
    }

    fn polyline_class(&mut self, points: &[(f64, f64)], color: Rgb, width: f64, class: &str) {
        let class = format!(r#" class="{}""#, crate::error::xml_text(class));
        self.write_polyline(points, color, width, &class);
    }

    fn text(&mut self, x: f64, y: f64, text: &str, style: TextStyle) {
        let a = match style.anchor {
            Anchor::Start => "start",
            Anchor::Middle => "middle",
            Anchor::End => "end",
        };
        let rot = if style.vertical {
            format!(r#" transform="rotate(-90 {} {})""#, fmt_px(x), fmt_px(y))
        } else {
            String::new()
        };
        let _ = writeln!(
            self.body,
            r#"<text x="{}" y="{}" font-size="{}" text-anchor="{a}" fill="{}"{rot}>{}</text>"#,
            fmt_px(x),
            fmt_px(y),
            fmt_px(style.size),
            style.color.hex(),
            crate::error::xml_text(text)
        );
    }
}

/// A raster image being drawn with tiny-skia (antialiased).
pub struct PngCanvas {
    pixmap: Pixmap,
    world: Option<WorldToPixel>,
}

impl PngCanvas {
    /// A white image of `width × height` pixels.
    pub fn new(width: u32, height: u32) -> Result<PngCanvas> {
        let mut pixmap = Pixmap::new(width.max(1), height.max(1)).ok_or_else(|| {
            Error::Impossible(format!("cannot make an image of {width} × {height} pixels"))
        })?;
        pixmap.fill(tiny_skia::Color::WHITE);
        Ok(PngCanvas {
            pixmap,
            world: None,
        })
    }

    /// Draws over an existing image (a 3D rendering, for its legend).
    pub fn from_pixmap(pixmap: Pixmap) -> PngCanvas {
        PngCanvas {
            pixmap,
            world: None,
        }
    }

    /// The PNG file's bytes.
    pub fn encode(&self) -> Result<Vec<u8>> {
        self.pixmap
            .encode_png()
            .map_err(|e| Error::Impossible(format!("PNG encoding failed: {e}")))
    }

    fn to_px(&self, x: f64, y: f64) -> (f32, f32) {
        match self.world {
            Some(w) => {
                let (a, b) = w.apply(x, y);
                (a as f32, b as f32)
            }
            None => (x as f32, y as f32),
        }
    }

    fn len_px(&self, l: f64) -> f32 {
        match self.world {
            Some(w) => (l * w.scale) as f32,
            None => l as f32,
        }
    }

    fn paint(c: Rgb) -> Paint<'static> {
        let mut p = Paint::default();
        p.set_color_rgba8(c.0, c.1, c.2, 255);
        p.anti_alias = true;
        p
    }

    fn draw_path(&mut self, path: &tiny_skia::Path, style: Style) {
        if let Some(c) = style.fill {
            self.pixmap.fill_path(
                path,
                &Self::paint(c),
                FillRule::Winding,
                Transform::identity(),
                None,
            );
        }
        if let Some((c, w)) = style.stroke {
            let stroke = Stroke {
                width: w as f32,
                ..Stroke::default()
            };
            self.pixmap
                .stroke_path(path, &Self::paint(c), &stroke, Transform::identity(), None);
        }
    }

    /// An open path through `points`, in pixels.
    fn path_through(&self, points: &[(f64, f64)]) -> PathBuilder {
        let mut pb = PathBuilder::new();
        for (k, &(x, y)) in points.iter().enumerate() {
            let (px, py) = self.to_px(x, y);
            if k == 0 {
                pb.move_to(px, py);
            } else {
                pb.line_to(px, py);
            }
        }
        pb
    }

    /// Blends `color` with coverage `alpha` into pixel `(x, y)` (white-ish
    /// backgrounds; the pixmap is opaque, so premultiplied equals straight).
    fn blend(&mut self, x: i64, y: i64, color: Rgb, alpha: f32) {
        let (w, h) = (self.pixmap.width() as i64, self.pixmap.height() as i64);
        if x < 0 || y < 0 || x >= w || y >= h || alpha <= 0.0 {
            return;
        }
        let a = alpha.min(1.0);
        let i = 4 * (y * w + x) as usize;
        let data = self.pixmap.data_mut();
        for (k, c) in [color.0, color.1, color.2].into_iter().enumerate() {
            let old = data[i + k] as f32;
            data[i + k] = (old + (c as f32 - old) * a).round() as u8;
        }
        data[i + 3] = 255;
    }
}

impl Canvas for PngCanvas {
    fn size(&self) -> (u32, u32) {
        (self.pixmap.width(), self.pixmap.height())
    }

    fn set_world(&mut self, world: Option<WorldToPixel>) {
        self.world = world;
    }

    fn rect(&mut self, x: f64, y: f64, w: f64, h: f64, style: Style) {
        let (x0, y0) = self.to_px(x, y);
        let (x1, y1) = self.to_px(x + w, y + h);
        let r = Rect::from_ltrb(x0.min(x1), y0.min(y1), x0.max(x1), y0.max(y1));
        if let Some(r) = r {
            let path = PathBuilder::from_rect(r);
            self.draw_path(&path, style);
        }
    }

    fn circle(&mut self, cx: f64, cy: f64, r: f64, style: Style, _class: &str) {
        let (x, y) = self.to_px(cx, cy);
        if let Some(path) = PathBuilder::from_circle(x, y, self.len_px(r)) {
            self.draw_path(&path, style);
        }
    }

    fn polyline(&mut self, points: &[(f64, f64)], color: Rgb, width: f64) {
        if let Some(path) = self.path_through(points).finish() {
            let stroke = Stroke {
                width: width as f32,
                line_join: tiny_skia::LineJoin::Round,
                ..Stroke::default()
            };
            self.pixmap.stroke_path(
                &path,
                &Self::paint(color),
                &stroke,
                Transform::identity(),
                None,
            );
        }
    }

    fn polygon(&mut self, points: &[(f64, f64)], style: Style) {
        let mut pb = self.path_through(points);
        pb.close();
        if let Some(path) = pb.finish() {
            self.draw_path(&path, style);
        }
    }

    fn text(&mut self, x: f64, y: f64, text: &str, style: TextStyle) {
        let f = font();
        let scale = PxScale::from(style.size as f32);
        let scaled = f.as_scaled(scale);
        let width = text_width(text, style.size);
        let start = match style.anchor {
            Anchor::Start => 0.0,
            Anchor::Middle => -width / 2.0,
            Anchor::End => -width,
        } as f32;
        let mut pen = start;
        let mut prev = None;
        let mut glyphs = Vec::new();
        for ch in text.chars() {
            let id = f.glyph_id(ch);
            if let Some(p) = prev {
                pen += scaled.kern(p, id);
            }
            glyphs.push(id.with_scale_and_position(scale, ab_glyph::point(pen, 0.0)));
            pen += scaled.h_advance(id);
            prev = Some(id);
        }
        // Whole-pixel origin keeps glyph stems crisp.
        let (ox, oy) = (x.round() as i64, y.round() as i64);
        for g in glyphs {
            if let Some(outline) = f.outline_glyph(g) {
                let b = outline.px_bounds();
                let mut cover = Vec::new();
                outline.draw(|gx, gy, c| cover.push((gx, gy, c)));
                for (gx, gy, c) in cover {
                    // Layout coordinates: along the text, and below the baseline.
                    let u = b.min.x as i64 + gx as i64;
                    let v = b.min.y as i64 + gy as i64;
                    let (px, py) = if style.vertical {
                        (ox + v, oy - u)
                    } else {
                        (ox + u, oy + v)
                    };
                    self.blend(px, py, style.color, c);
                }
            }
        }
    }
}
