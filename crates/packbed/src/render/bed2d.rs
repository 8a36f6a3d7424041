//! 2D beds: every disc drawn exactly, the box outline, the contact network, and
//! chains drawn as one body (the outline of the union of their beads).
//!
//! The discs are written in bed coordinates under one SVG transform, so the SVG
//! holds the exact positions and radii (`<circle class="particle">`, one per disc,
//! in `particles.csv` order).

use super::canvas::{Canvas, PngCanvas, Rgb, Style, SvgCanvas, WorldToPixel};
use super::frame::{self, Frame};
use super::{contacts_if_needed, default_title, picture_palette, RenderOptions};
use crate::bed::Bed;
use crate::error::Result;

/// The SVG picture of a 2D bed.
pub fn svg(bed: &Bed<2>, opts: &RenderOptions) -> Result<String> {
    let mut c = SvgCanvas::new(opts.width, opts.height);
    draw(&mut c, bed, opts)?;
    Ok(c.finish())
}

/// The PNG picture of a 2D bed.
pub fn png(bed: &Bed<2>, opts: &RenderOptions) -> Result<Vec<u8>> {
    let mut c = PngCanvas::new(opts.width, opts.height)?;
    draw(&mut c, bed, opts)?;
    c.encode()
}

/// Where the box lands in the picture area: the largest scale that fits, centred.
pub fn world_to_pixel(frame: &Frame, width: f64, height: f64) -> WorldToPixel {
    let [l, t, r, b] = frame.area;
    let scale = ((r - l) / width).min((b - t) / height);
    let tx = l + 0.5 * ((r - l) - scale * width);
    let ty = b - 0.5 * ((b - t) - scale * height);
    WorldToPixel { scale, tx, ty }
}

/// Where `draw` puts the bed in the image: bed coordinates to pixels.
pub fn placement(bed: &Bed<2>, opts: &RenderOptions) -> Result<WorldToPixel> {
    let contacts = contacts_if_needed(bed, opts);
    let pal = picture_palette(bed, opts, contacts.as_ref())?;
    let frame = frame::layout(opts.width, opts.height, &pal);
    let size = bed.container.size;
    Ok(world_to_pixel(&frame, size[0], size[1].max(bed.top())))
}

/// Draws a 2D bed with its frame on any canvas.
pub fn draw(canvas: &mut dyn Canvas, bed: &Bed<2>, opts: &RenderOptions) -> Result<()> {
    let contacts = contacts_if_needed(bed, opts);
    let pal = picture_palette(bed, opts, contacts.as_ref())?;
    let mut frame = frame::layout(opts.width, opts.height, &pal);
    frame.length_unit = super::run_plots::length_label(opts.length_unit);
    let size = bed.container.size;
    // Count mode can build above the roof: show the whole bed.
    let height = size[1].max(bed.top());
    let world = world_to_pixel(&frame, size[0], height);
    let s = world.scale;

    canvas.set_world(Some(world));
    // Outlines thin enough not to swamp small discs; none when discs are specks.
    let r_min_px = bed.r_min() * s;
    let outline =
        (opts.outlines && r_min_px >= 2.5).then(|| (Rgb::DARK, (0.06 * r_min_px).clamp(0.5, 1.2)));
    let fade = if opts.network { 0.55 } else { 0.0 };

    let mut k = 0;
    while k < bed.len() {
        // Beads of a body are consecutive in packbed's beds; a run of one body.
        let mut end = k + 1;
        while end < bed.len() && bed.bodies[end] == bed.bodies[k] {
            end += 1;
        }
        let fill = |i: usize| pal.colours[i].mix(Rgb::WHITE, fade);
        if end - k == 1 {
            let style = Style {
                fill: Some(fill(k)),
                stroke: outline,
            };
            let c = bed.centres[k];
            canvas.circle(c[0], c[1], bed.radii[k], style, "particle");
        } else {
            // A chain: outlines of every bead first, then the fills on top, which
            // hide the outlines inside the body and leave the union's outline.
            if let Some((oc, ow)) = outline {
                for i in k..end {
                    let c = bed.centres[i];
                    canvas.circle(
                        c[0],
                        c[1],
                        bed.radii[i],
                        Style::stroke(oc, 2.0 * ow),
                        "bead-outline",
                    );
                }
            }
            for i in k..end {
                let c = bed.centres[i];
                canvas.circle(c[0], c[1], bed.radii[i], Style::fill(fill(i)), "particle");
            }
        }
        k = end;
    }

    if let (true, Some(contacts)) = (opts.network, &contacts) {
        let lw = (0.18 * r_min_px).clamp(0.6, 3.0);
        for c in &contacts.pairs {
            let (i, j) = (c.i as usize, c.j as usize);
            let a = bed.centres[i];
            let d = bed.container.displacement(&a, &bed.centres[j]);
            canvas.line(a[0], a[1], a[0] + d[0], a[1] + d[1], Rgb::BLACK, lw);
            if bed.container.periodic && (a + d - bed.centres[j]).norm() > 1e-9 * size[0] {
                // Across a periodic side: the other half from the other end.
                let b = bed.centres[j];
                canvas.line(b[0], b[1], b[0] - d[0], b[1] - d[1], Rgb::BLACK, lw);
            }
        }
    }

    // The box on top, so discs touching a wall do not hide it.
    let lw = (frame.font / 10.0).max(1.5);
    canvas.rect(0.0, 0.0, size[0], size[1], Style::stroke(Rgb::BLACK, lw));
    canvas.set_world(None);

    let title = opts
        .title
        .clone()
        .unwrap_or_else(|| default_title(bed, opts));
    frame::draw(canvas, &frame, &title, &pal, s, "", world.tx);
    Ok(())
}
