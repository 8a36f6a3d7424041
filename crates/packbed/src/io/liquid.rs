//! The drainage's files: `drainage.csv` (the capillary pressure–saturation
//! curve) and `liquid.csv` (the pendular bridges at the reported pressure,
//! one row per pair of particles).

use crate::analysis::pores::drainage::Drainage;
use serde::Serialize;
use std::io::Write;

/// The drainage's file names, in writing order.
pub const LIQUID_FILES: [&str; 2] = ["drainage.csv", "liquid.csv"];

/// Writes `drainage.csv`: one row per capillary pressure, `pc_reduced`
/// (`P_c·d32/γ`), `pc_pa` (empty without a length unit), the wetting
/// saturation and its parts (`connected`, `trapped`, `pendular`).
pub fn write_curve(w: &mut dyn Write, d: &Drainage) -> std::io::Result<()> {
    let mut out = csv::Writer::from_writer(w);
    for row in &d.curve {
        out.serialize(row).map_err(std::io::Error::other)?;
    }
    out.flush()
}

/// A row of `liquid.csv`.
#[derive(Serialize)]
struct BridgeLine {
    particle_a: u32,
    particle_b: u32,
    sx: i8,
    sy: i8,
    gap: f64,
    volume: f64,
    neck_radius: f64,
    filling_angle_a: f64,
    filling_angle_b: f64,
    state: &'static str,
}

/// Writes `liquid.csv`: per pendular bridge at the reported pressure, its
/// two particles, the periods b lies from a (`sx`, `sy`), the surface gap,
/// the liquid volume (area in 2D) in the slab's pores, the neck radius and
/// the filling angles in degrees, `state` = `pendular`.
pub fn write_bridges(w: &mut dyn Write, d: &Drainage) -> std::io::Result<()> {
    let mut out = csv::Writer::from_writer(w);
    if d.bridges.is_empty() {
        // The header alone: a table with no rows still names its columns.
        out.write_record([
            "particle_a",
            "particle_b",
            "sx",
            "sy",
            "gap",
            "volume",
            "neck_radius",
            "filling_angle_a",
            "filling_angle_b",
            "state",
        ])
        .map_err(std::io::Error::other)?;
    }
    for b in &d.bridges {
        out.serialize(BridgeLine {
            particle_a: b.particles[0],
            particle_b: b.particles[1],
            sx: b.shift[0],
            sy: b.shift[1],
            gap: b.gap,
            volume: b.volume,
            neck_radius: b.neck_radius,
            filling_angle_a: b.filling_angle[0],
            filling_angle_b: b.filling_angle[1],
            state: "pendular",
        })
        .map_err(std::io::Error::other)?;
    }
    out.flush()
}
