//! Plots from plain data: grouped bars (histograms, regional packing, with
//! optional error bars) and x–y series (profiles, sweeps, with optional error
//! bars). Any measure that produces counts, bars or points can be drawn without
//! this module knowing about it. Margins are sized from the text they hold, so
//! no label is clipped.

// `!(x > y)` keeps NaN on the safe branch.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::canvas::{
    cap_height, text_width, Anchor, Canvas, PngCanvas, Rgb, Style, SvgCanvas, TextStyle,
};
use super::colour;
use crate::error::{Error, Result};

/// A group of bars: one value per category (e.g. one species' histogram).
#[derive(Clone, Debug, PartialEq)]
pub struct BarGroup {
    /// Legend name.
    pub name: String,
    /// One value per category.
    pub values: Vec<f64>,
    /// Error half-widths (e.g. standard deviations), one per category.
    pub errors: Option<Vec<f64>>,
}

/// A series of points joined by lines.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    /// Legend name.
    pub name: String,
    /// The points, in drawing order.
    pub points: Vec<(f64, f64)>,
    /// Error half-widths in y, one per point.
    pub errors: Option<Vec<f64>>,
    /// Draw a marker at each point.
    pub markers: bool,
    /// A shaded band `(low, high)` in y, one per point (an ensemble's
    /// scatter about its mean curve), drawn under every line.
    pub band: Option<Vec<(f64, f64)>>,
}

/// What a plot shows.
#[derive(Clone, Debug, PartialEq)]
pub enum PlotData {
    /// Side-by-side bars per category.
    Bars {
        /// Category names along the x axis (e.g. "0", "1", … or region names).
        categories: Vec<String>,
        /// One group per data set.
        groups: Vec<BarGroup>,
    },
    /// A dot (with its error bar) per category and group: for values whose
    /// differences matter more than their distance from zero (packing
    /// fractions), so the axis spans the data, which a bar must not.
    Dots {
        /// Category names along the x axis.
        categories: Vec<String>,
        /// One group per data set.
        groups: Vec<BarGroup>,
    },
    /// Lines through points.
    Lines {
        /// The series.
        series: Vec<Series>,
    },
    /// Lines through points over a logarithmic x axis (sizes spanning
    /// decades, as size distributions are drawn); every x must be positive.
    LogLines {
        /// The series.
        series: Vec<Series>,
    },
}

/// A plot: data, title and axis labels (with units).
#[derive(Clone, Debug, PartialEq)]
pub struct Plot {
    /// Title on top.
    pub title: String,
    /// Label of the x axis.
    pub x_label: String,
    /// Label of the y axis.
    pub y_label: String,
    /// The data.
    pub data: PlotData,
    /// Fixed y range (e.g. 0–100 %); else from the data.
    pub y_range: Option<(f64, f64)>,
    /// Fixed x range for lines; else from the data.
    pub x_range: Option<(f64, f64)>,
}

impl Plot {
    /// The plot as an SVG document.
    pub fn to_svg(&self, width: u32, height: u32) -> Result<String> {
        let mut c = SvgCanvas::new(width, height);
        self.draw(&mut c)?;
        Ok(c.finish())
    }

    /// The plot as PNG bytes.
    pub fn to_png(&self, width: u32, height: u32) -> Result<Vec<u8>> {
        let mut c = PngCanvas::new(width, height)?;
        self.draw(&mut c)?;
        c.encode()
    }

    /// Refuses data that cannot be drawn honestly.
    fn check(&self) -> Result<()> {
        let bad = |what: &str| {
            Err(Error::Impossible(format!(
                "plot \"{}\": {what}",
                self.title
            )))
        };
        match &self.data {
            PlotData::Bars { categories, groups } | PlotData::Dots { categories, groups } => {
                for g in groups {
                    if g.values.len() != categories.len() {
                        return bad("a bar group has a different number of values than categories");
                    }
                    if g.values.iter().any(|v| !v.is_finite()) {
                        return bad("a bar value is not a finite number");
                    }
                    if let Some(e) = &g.errors {
                        if e.len() != g.values.len() || e.iter().any(|v| !v.is_finite()) {
                            return bad("error bars do not match the values");
                        }
                    }
                }
            }
            PlotData::Lines { series } | PlotData::LogLines { series } => {
                let log = matches!(self.data, PlotData::LogLines { .. });
                for s in series {
                    if s.points
                        .iter()
                        .any(|p| !p.0.is_finite() || !p.1.is_finite())
                    {
                        return bad("a point is not finite");
                    }
                    if log && s.points.iter().any(|p| p.0 <= 0.0) {
                        return bad("a point on a logarithmic axis is not positive");
                    }
                    if let Some(e) = &s.errors {
                        if e.len() != s.points.len() || e.iter().any(|v| !v.is_finite()) {
                            return bad("error bars do not match the points");
                        }
                    }
                    if let Some(b) = &s.band {
                        if b.len() != s.points.len()
                            || b.iter().any(|v| !v.0.is_finite() || !v.1.is_finite())
                        {
                            return bad("a band does not match the points");
                        }
                    }
                }
            }
        }
        Ok(())
    }

    /// Draws the plot on any canvas.
    pub fn draw(&self, canvas: &mut dyn Canvas) -> Result<()> {
        self.check()?;
        let (w, h) = canvas.size();
        let (w, h) = (w as f64, h as f64);
        let f = (w.min(h) / 32.0).clamp(10.0, 28.0);
        let small = 0.85 * f;

        // Data ranges.
        let (xr, yr) = self.ranges();
        let yticks = ticks(yr.0, yr.1, 6);
        let ylab_w = yticks
            .iter()
            .map(|&t| text_width(&format_tick(t, tick_step(&yticks)), small))
            .fold(0.0, f64::max);
        // A name of any length (a species named by a sentence) is shortened
        // to 40 % of the width rather than crowding out the plot; names that
        // fitted before (the pore plot's "constrictions (39018 in the slab)")
        // stay whole.
        let names: Vec<String> = self
            .legend_names()
            .iter()
            .map(|n| fit(n, small, 0.4 * w))
            .collect();
        let legend_w = if names.len() > 1 {
            names
                .iter()
                .map(|n| text_width(n, small))
                .fold(0.0, f64::max)
                + 2.2 * small
                + f
        } else {
            0.0
        };
        let left = f + 1.2 * f + 0.6 * f + ylab_w + 0.5 * f;
        let right = w - f - legend_w;
        let top = f + 1.2 * f + f;
        let bottom = h - (f + 1.2 * f + 0.8 * f + cap_height(small) + 0.6 * f);
        if right - left < 40.0 || bottom - top < 40.0 {
            return Err(Error::Impossible(format!(
                "plot \"{}\": {w} × {h} pixels is too small for its labels",
                self.title
            )));
        }
        let ymap = |y: f64| bottom - (y - yr.0) / (yr.1 - yr.0) * (bottom - top);

        // Title (shrunk to the width if long) and axis labels.
        let tsize =
            (1.15 * f).min(1.15 * f * (w - 2.0 * f) / text_width(&self.title, 1.15 * f).max(1.0));
        canvas.text(
            w / 2.0,
            f + cap_height(tsize),
            &self.title,
            TextStyle::new(tsize, Anchor::Middle),
        );
        let xl = f.min(f * (right - left) / text_width(&self.x_label, f).max(1.0));
        canvas.text(
            (left + right) / 2.0,
            h - f,
            &self.x_label,
            TextStyle::new(xl, Anchor::Middle),
        );
        let yl = f.min(f * (bottom - top) / text_width(&self.y_label, f).max(1.0));
        canvas.text(
            f + cap_height(yl),
            (top + bottom) / 2.0,
            &self.y_label,
            TextStyle::new(yl, Anchor::Middle).vertical(),
        );

        // Horizontal grid and y ticks.
        let step = tick_step(&yticks);
        for &t in &yticks {
            let y = ymap(t);
            canvas.line(left, y, right, y, Rgb(225, 225, 225), 1.0);
            canvas.text(
                left - 0.5 * f,
                y + cap_height(small) / 2.0,
                &format_tick(t, step),
                TextStyle::new(small, Anchor::End),
            );
        }
        let xtick_y = bottom + 0.6 * f + cap_height(small);

        match &self.data {
            PlotData::Bars { categories, groups } | PlotData::Dots { categories, groups } => {
                let dots = matches!(self.data, PlotData::Dots { .. });
                let n = categories.len().max(1) as f64;
                let slot = (right - left) / n;
                let gw = 0.8 * slot / groups.len().max(1) as f64;
                // Label every k-th category so labels never collide.
                let widest = categories
                    .iter()
                    .map(|c| text_width(c, small).min((right - left) / 3.0))
                    .fold(0.0, f64::max);
                let every = ((widest + 0.5 * f) / slot).ceil().max(1.0) as usize;
                for (k, cat) in categories.iter().enumerate() {
                    let cx = left + (k as f64 + 0.5) * slot;
                    if k % every == 0 {
                        let cat = fit(cat, small, (right - left) / 3.0);
                        canvas.text(cx, xtick_y, &cat, TextStyle::new(small, Anchor::Middle));
                    }
                }
                for (g, group) in groups.iter().enumerate() {
                    let c = colour::categorical(g);
                    for (k, &v) in group.values.iter().enumerate() {
                        let x0 = left + k as f64 * slot + 0.1 * slot + g as f64 * gw;
                        let xm = x0 + gw / 2.0;
                        if !dots {
                            let (ya, yb) = (ymap(v.max(yr.0)), ymap(0f64.max(yr.0)));
                            canvas.rect(x0, ya.min(yb), gw, (ya - yb).abs(), Style::fill(c));
                        }
                        // Dots get caps of a fixed size: a slot-wide cap
                        // would read as a bar.
                        let cap = if dots { 0.4 * f } else { gw / 4.0 };
                        let ink = if dots { c } else { Rgb::BLACK };
                        if let Some(e) = &group.errors {
                            // A bar is cut where it leaves the axis (a fixed
                            // range that stops at 0 for a positive measure).
                            let (lo, hi) = (
                                ymap((v - e[k]).max(yr.0).min(yr.1)),
                                ymap((v + e[k]).max(yr.0).min(yr.1)),
                            );
                            canvas.line(xm, lo, xm, hi, ink, 1.2);
                            canvas.line(xm - cap, lo, xm + cap, lo, ink, 1.2);
                            canvas.line(xm - cap, hi, xm + cap, hi, ink, 1.2);
                        }
                        if dots {
                            let style = Style::both(c, Rgb::WHITE, 1.0);
                            canvas.circle(xm, ymap(v), 0.35 * f, style, "marker");
                        }
                    }
                }
            }
            PlotData::Lines { series } | PlotData::LogLines { series } => {
                let log = matches!(self.data, PlotData::LogLines { .. });
                // A log axis keeps its range in decades (`ranges`).
                let axis = |x: f64| if log { x.log10() } else { x };
                let xmap = |x: f64| left + (axis(x) - xr.0) / (xr.1 - xr.0) * (right - left);
                let labels: Vec<(f64, String)> = if log {
                    log_ticks(xr.0, xr.1)
                        .into_iter()
                        .map(|t| (t, format_number(t)))
                        .collect()
                } else {
                    let xticks = ticks(xr.0, xr.1, 7);
                    let xstep = tick_step(&xticks);
                    xticks.iter().map(|&t| (t, format_tick(t, xstep))).collect()
                };
                for (t, label) in &labels {
                    let x = xmap(*t);
                    canvas.line(x, bottom, x, bottom + 0.3 * f, Rgb::BLACK, 1.0);
                    if log {
                        canvas.line(x, top, x, bottom, Rgb(235, 235, 235), 1.0);
                    }
                    canvas.text(x, xtick_y, label, TextStyle::new(small, Anchor::Middle));
                }
                // Bands first, light, so that no band hides another's line.
                for (g, s) in series.iter().enumerate() {
                    if let Some(b) = &s.band {
                        let upper = s.points.iter().zip(b).map(|(p, b)| (xmap(p.0), ymap(b.1)));
                        let lower = s.points.iter().zip(b).rev();
                        let ring: Vec<(f64, f64)> = upper
                            .chain(lower.map(|(p, b)| (xmap(p.0), ymap(b.0))))
                            .collect();
                        let light = colour::categorical(g).mix(Rgb::WHITE, 0.72);
                        canvas.polygon(&ring, Style::fill(light));
                    }
                }
                for (g, s) in series.iter().enumerate() {
                    let c = colour::categorical(g);
                    let pts: Vec<(f64, f64)> =
                        s.points.iter().map(|&(x, y)| (xmap(x), ymap(y))).collect();
                    if pts.len() > 1 {
                        canvas.polyline(&pts, c, (f / 7.0).max(1.5));
                    }
                    if let Some(e) = &s.errors {
                        for (k, &(x, y)) in s.points.iter().enumerate() {
                            let (xm, lo, hi) = (xmap(x), ymap(y - e[k]), ymap(y + e[k]));
                            let cap = 0.3 * f;
                            canvas.line(xm, lo, xm, hi, c, 1.2);
                            canvas.line(xm - cap, lo, xm + cap, lo, c, 1.2);
                            canvas.line(xm - cap, hi, xm + cap, hi, c, 1.2);
                        }
                    }
                    if s.markers || pts.len() == 1 {
                        for &(x, y) in &pts {
                            canvas.circle(
                                x,
                                y,
                                0.25 * f,
                                Style::both(c, Rgb::WHITE, 1.0),
                                "marker",
                            );
                        }
                    }
                }
            }
        }
        // Axes.
        canvas.line(left, top, left, bottom, Rgb::BLACK, 1.2);
        canvas.line(left, bottom, right, bottom, Rgb::BLACK, 1.2);

        // Legend on the right.
        if names.len() > 1 {
            let x = right + f;
            let mut y = top + cap_height(small);
            for (g, name) in names.iter().enumerate() {
                let sw = 0.9 * small;
                canvas.rect(
                    x,
                    y - cap_height(small),
                    sw,
                    sw,
                    Style::fill(colour::categorical(g)),
                );
                canvas.text(
                    x + sw + 0.4 * small,
                    y,
                    name,
                    TextStyle::new(small, Anchor::Start),
                );
                y += 1.6 * small;
            }
        }
        Ok(())
    }

    fn legend_names(&self) -> Vec<String> {
        match &self.data {
            PlotData::Bars { groups, .. } | PlotData::Dots { groups, .. } => {
                groups.iter().map(|g| g.name.clone()).collect()
            }
            PlotData::Lines { series } | PlotData::LogLines { series } => {
                series.iter().map(|s| s.name.clone()).collect()
            }
        }
    }

    /// Data ranges `(x, y)`, padded; bars start at zero, dots span the data.
    pub(crate) fn ranges(&self) -> ((f64, f64), (f64, f64)) {
        let (mut x0, mut x1, mut y0, mut y1) = (
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        );
        match &self.data {
            PlotData::Bars { groups, .. } | PlotData::Dots { groups, .. } => {
                // A bar starts at 0, so its axis must hold 0; a dot's need not.
                if matches!(self.data, PlotData::Bars { .. }) {
                    y0 = 0.0;
                    y1 = 0.0;
                }
                for g in groups {
                    for (k, &v) in g.values.iter().enumerate() {
                        let e = g.errors.as_ref().map_or(0.0, |e| e[k].abs());
                        y0 = y0.min(v - e);
                        y1 = y1.max(v + e);
                    }
                }
                x0 = 0.0;
                x1 = 1.0;
            }
            PlotData::Lines { series } | PlotData::LogLines { series } => {
                let log = matches!(self.data, PlotData::LogLines { .. });
                for s in series {
                    for (k, &(x, y)) in s.points.iter().enumerate() {
                        let e = s.errors.as_ref().map_or(0.0, |e| e[k].abs());
                        let (lo, hi) = s.band.as_ref().map_or((y, y), |b| b[k]);
                        let x = if log { x.log10() } else { x };
                        x0 = x0.min(x);
                        x1 = x1.max(x);
                        y0 = y0.min(y - e).min(lo);
                        y1 = y1.max(y + e).max(hi);
                    }
                }
            }
        }
        let pad = |a: f64, b: f64, zero_floor: bool| -> (f64, f64) {
            if !a.is_finite() || !b.is_finite() {
                return (0.0, 1.0);
            }
            if b - a <= 1e-12 * (a.abs() + b.abs()).max(1e-300) {
                return (a - 0.5 - 0.5 * a.abs(), b + 0.5 + 0.5 * b.abs());
            }
            let lo = if zero_floor && a >= 0.0 {
                a
            } else {
                a - 0.05 * (b - a)
            };
            (lo, b + 0.05 * (b - a))
        };
        let is_bars = matches!(self.data, PlotData::Bars { .. });
        let xr = match (self.x_range, &self.data) {
            (Some((a, b)), PlotData::LogLines { .. }) => (a.log10(), b.log10()),
            (Some(r), _) => r,
            (None, _) => pad(x0, x1, false),
        };
        let yr = self.y_range.unwrap_or_else(|| pad(y0, y1, is_bars));
        // Round the y range out to whole ticks.
        let t = ticks(yr.0, yr.1, 6);
        let yr = if self.y_range.is_none() && t.len() >= 2 {
            let st = tick_step(&t);
            ((yr.0 / st).floor() * st, (yr.1 / st).ceil() * st)
        } else {
            yr
        };
        (xr, yr)
    }
}

/// Ticks of a logarithmic axis from `10^lo` to `10^hi`: 1, 2 and 5 times the
/// powers of ten, or every digit where that gives fewer than three.
pub fn log_ticks(lo: f64, hi: f64) -> Vec<f64> {
    let of = |digits: &[f64]| -> Vec<f64> {
        let mut v = Vec::new();
        let (a, b) = (lo.floor() as i32, hi.ceil() as i32);
        for k in a..=b {
            for &m in digits {
                let t = m * 10f64.powi(k);
                let l = t.log10();
                if l >= lo - 1e-9 && l <= hi + 1e-9 {
                    v.push(t);
                }
            }
        }
        v
    };
    let coarse = of(&[1.0, 2.0, 5.0]);
    if coarse.len() >= 3 {
        coarse
    } else {
        of(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0])
    }
}

/// The largest of 1, 2, 5 × 10^k not above `x` (0 for `x <= 0`).
pub fn nice_floor(x: f64) -> f64 {
    if !(x > 0.0 && x.is_finite()) {
        return 0.0;
    }
    let p = 10f64.powf(x.log10().floor());
    let m = x / p;
    let n = if m >= 5.0 {
        5.0
    } else if m >= 2.0 {
        2.0
    } else {
        1.0
    };
    n * p
}

/// Round tick values covering `[lo, hi]`, about `target` of them.
pub fn ticks(lo: f64, hi: f64, target: usize) -> Vec<f64> {
    if !(hi > lo) || !lo.is_finite() || !hi.is_finite() {
        return vec![lo];
    }
    let raw = (hi - lo) / target.max(1) as f64;
    let mut step = nice_floor(raw);
    if step < raw * 0.7 {
        // 1-2-5 steps: take the next one up when the floor is much too fine.
        let m = step / 10f64.powf(step.log10().floor());
        step *= if m == 2.0 { 2.5 } else { 2.0 };
    }
    let first = (lo / step).ceil();
    let last = (hi / step).floor();
    let n = (last - first) as i64;
    (0..=n.max(0)).map(|k| (first + k as f64) * step).collect()
}

fn tick_step(t: &[f64]) -> f64 {
    if t.len() >= 2 {
        t[1] - t[0]
    } else {
        1.0
    }
}

/// A tick label with as many decimals as the step needs (no "0.30000000000000004").
pub fn format_tick(v: f64, step: f64) -> String {
    let decimals = if step > 0.0 && step.is_finite() {
        (-(step.log10().floor())).max(0.0) as usize
    } else {
        0
    };
    let s = format!("{:.*}", decimals.min(12), v);
    if s.starts_with('-') && s[1..].chars().all(|c| c == '0' || c == '.') {
        s[1..].to_string()
    } else {
        s
    }
}

/// A number for a label: up to 4 significant digits, no trailing zeros.
pub fn format_number(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let digits = (3 - v.abs().log10().floor() as i64).clamp(0, 12) as usize;
    let s = format!("{:.*}", digits, v);
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// `text` cut with an ellipsis to fit `max_w` at `size` (whole when it fits).
fn fit(text: &str, size: f64, max_w: f64) -> String {
    if text_width(text, size) <= max_w {
        return text.to_string();
    }
    let chars: Vec<char> = text.chars().collect();
    let cut = |n: usize| chars[..n].iter().collect::<String>() + "…";
    // The longest prefix that fits: widths grow with the prefix.
    let (mut lo, mut hi) = (0, chars.len());
    while lo < hi {
        let mid = (lo + hi).div_ceil(2);
        if text_width(&cut(mid), size) <= max_w {
            lo = mid;
        } else {
            hi = mid - 1;
        }
    }
    cut(lo)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nice_numbers() {
        assert_eq!(nice_floor(7.3), 5.0);
        assert_eq!(nice_floor(0.034), 0.02);
        assert_eq!(nice_floor(100.0), 100.0);
        assert_eq!(nice_floor(0.0), 0.0);
        assert_eq!(
            ticks(0.0, 1.0, 5),
            vec![0.0, 0.2, 0.4, 0.6000000000000001, 0.8, 1.0]
        );
        assert_eq!(
            ticks(0.0, 100.0, 5),
            vec![0.0, 20.0, 40.0, 60.0, 80.0, 100.0]
        );
        assert_eq!(format_tick(0.6000000000000001, 0.2), "0.6");
        assert_eq!(format_tick(-0.0, 0.5), "0.0");
        assert_eq!(format_tick(40.0, 20.0), "40");
        assert_eq!(format_number(20.0), "20");
        assert_eq!(format_number(0.12345), "0.1235");
        assert_eq!(format_number(1234.7), "1235");
    }

    #[test]
    fn mismatched_data_is_refused() {
        let p = Plot {
            title: "t".into(),
            x_label: "x".into(),
            y_label: "y".into(),
            data: PlotData::Bars {
                categories: vec!["a".into(), "b".into()],
                groups: vec![BarGroup {
                    name: "g".into(),
                    values: vec![1.0],
                    errors: None,
                }],
            },
            y_range: None,
            x_range: None,
        };
        assert!(p.to_svg(600, 400).is_err());
        // A band must have one (low, high) per point, finite.
        let banded = |band: Vec<(f64, f64)>| Plot {
            data: PlotData::LogLines {
                series: vec![Series {
                    name: "s".into(),
                    points: vec![(1.0, 0.5), (10.0, 0.2)],
                    errors: None,
                    markers: false,
                    band: Some(band),
                }],
            },
            ..p.clone()
        };
        assert!(banded(vec![(0.4, 0.6)]).to_svg(600, 400).is_err());
        assert!(banded(vec![(0.4, 0.6), (0.1, f64::NAN)])
            .to_svg(600, 400)
            .is_err());
        let svg = banded(vec![(0.4, 0.6), (0.1, 0.3)])
            .to_png(600, 400)
            .and_then(|_| banded(vec![(0.4, 0.6), (0.1, 0.3)]).to_svg(600, 400))
            .unwrap();
        assert_eq!(svg.matches("<polygon").count(), 1);
    }

    #[test]
    fn long_names_are_shortened_not_fatal() {
        let long = "n".repeat(300);
        let group = |name: &str| BarGroup {
            name: name.into(),
            values: vec![1.0, 2.0],
            errors: None,
        };
        let p = Plot {
            title: "t".into(),
            x_label: "x".into(),
            y_label: "y".into(),
            data: PlotData::Bars {
                categories: vec![long.clone(), "b".into()],
                groups: vec![group(&long), group("short")],
            },
            y_range: None,
            x_range: None,
        };
        let svg = p.to_svg(1000, 700).unwrap();
        assert!(svg.contains("nnn…<"), "no shortened name");
        assert!(!svg.contains(&long));
        assert!(svg.contains(">short<"));
        let cut = fit(&long, 10.0, 100.0);
        assert!(cut.ends_with('…') && text_width(&cut, 10.0) <= 100.0);
        assert_eq!(fit("short", 10.0, 100.0), "short");
    }
}
