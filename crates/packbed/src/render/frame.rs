//! The frame around a bed picture: a title on top, a legend on the right, a scale
//! bar below. Sizes come from the embedded font's metrics, so nothing is clipped.

use super::canvas::{cap_height, text_width, Anchor, Canvas, Rgb, Style, TextStyle};
use super::plot::{format_number, nice_floor};
use super::Palette;

/// Where things go in an image of a given size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// Base font size in pixels.
    pub font: f64,
    /// Picture area: left, top, right, bottom (pixels).
    pub area: [f64; 4],
    /// Left edge of the legend column.
    pub legend_x: f64,
    /// The unit the scale bar names ("length units" unless the run gave one).
    pub length_unit: &'static str,
}

/// Lays out a `width × height` image for this title and legend.
pub fn layout(width: u32, height: u32, palette: &Palette) -> Frame {
    let (w, h) = (width as f64, height as f64);
    let font = (w.min(h) / 42.0).clamp(11.0, 30.0);
    let pad = font;
    let swatch = font;
    let widest = palette
        .legend
        .iter()
        .map(|(_, l)| text_width(l, font))
        .chain(std::iter::once(text_width(&palette.heading, font)))
        .fold(0.0, f64::max);
    // The legend never takes more than 40% of the width; long labels shrink it.
    let legend_w = if palette.legend.is_empty() {
        0.0
    } else {
        (swatch * 1.6 + widest + pad).min(0.4 * w)
    };
    let top = pad + 1.3 * font + pad;
    let bottom = h - (pad + 2.4 * font);
    let left = pad;
    let right = w - pad - legend_w;
    Frame {
        font,
        area: [left, top, right.max(left + 10.0), bottom.max(top + 10.0)],
        legend_x: right + pad,
        length_unit: super::run_plots::length_label(None),
    }
}

/// Draws the title, the legend and a scale bar for `pixels_per_unit` starting
/// at pixel column `bar_x` (under the picture's left edge).
pub fn draw(
    canvas: &mut dyn Canvas,
    frame: &Frame,
    title: &str,
    palette: &Palette,
    pixels_per_unit: f64,
    scale_note: &str,
    bar_x: f64,
) {
    let f = frame.font;
    let (w, h) = canvas.size();
    let (w, h) = (w as f64, h as f64);
    // Title, shrunk to fit the width if it is long.
    let mut tsize = 1.2 * f;
    let avail = w - 2.0 * f;
    let tw = text_width(title, tsize);
    if tw > avail {
        tsize *= avail / tw;
    }
    canvas.text(
        w / 2.0,
        f + cap_height(tsize),
        title,
        TextStyle::new(tsize, Anchor::Middle),
    );

    // Legend: heading, then a swatch and a label per entry.
    let mut y = frame.area[1] + cap_height(f);
    let mut lsize = f;
    let avail_w = w - frame.legend_x - 0.5 * f;
    let widest = palette
        .legend
        .iter()
        .map(|(_, l)| text_width(l, f) + 1.6 * f)
        .fold(text_width(&palette.heading, f), f64::max);
    if widest > avail_w && widest > 0.0 {
        lsize = f * avail_w / widest;
    }
    let rows = palette.legend.len() as f64 + 1.0;
    let row_h = (1.6 * lsize).min((frame.area[3] - frame.area[1]) / rows.max(1.0));
    if !palette.heading.is_empty() {
        canvas.text(
            frame.legend_x,
            y,
            &palette.heading,
            TextStyle::new(lsize, Anchor::Start),
        );
        y += row_h;
    }
    for (c, label) in &palette.legend {
        let r = (0.3 * row_h).max(2.0);
        canvas.circle(
            frame.legend_x + r,
            y - cap_height(lsize) / 2.0,
            r,
            Style::both(*c, Rgb::DARK, 0.8),
            "legend",
        );
        canvas.text(
            frame.legend_x + 2.0 * r + 0.5 * lsize,
            y,
            label,
            TextStyle::new(lsize, Anchor::Start),
        );
        y += row_h;
    }

    // Scale bar: a round length near a quarter of the picture's width.
    if pixels_per_unit > 0.0 && pixels_per_unit.is_finite() {
        let area_w = frame.area[2] - frame.area[0];
        let len = nice_floor(0.25 * area_w / pixels_per_unit);
        if len > 0.0 {
            let px = len * pixels_per_unit;
            let x0 = bar_x.max(frame.area[0]);
            let yb = h - f - 1.3 * f;
            let tick = 0.4 * f;
            let lw = (f / 8.0).max(1.5);
            canvas.line(x0, yb, x0 + px, yb, Rgb::BLACK, lw);
            canvas.line(x0, yb - tick, x0, yb + tick, Rgb::BLACK, lw);
            canvas.line(x0 + px, yb - tick, x0 + px, yb + tick, Rgb::BLACK, lw);
            let unit = frame.length_unit;
            let label = format!("{} {unit}{scale_note}", format_number(len));
            let size = f.min(f * (w - x0 - px - 2.0 * f) / text_width(&label, f).max(1.0));
            canvas.text(
                x0 + px + 0.6 * f,
                yb + cap_height(size) / 2.0,
                &label,
                TextStyle::new(size, Anchor::Start),
            );
        }
    }
}
