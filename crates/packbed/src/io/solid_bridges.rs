//! The drying's files: `bridges.csv` (the solid each pair of particles
//! holds after drying, one row per pair) and `agglomerates.csv` (one row per
//! agglomerate, largest first).

use crate::analysis::pores::drying::Drying;
use serde::Serialize;
use std::io::Write;

/// The drying's file names, in writing order.
pub const DRYING_FILES: [&str; 2] = ["bridges.csv", "agglomerates.csv"];

/// A row of `bridges.csv`.
#[derive(Serialize)]
struct BridgeLine {
    particle_a: u32,
    particle_b: u32,
    sx: i8,
    sy: i8,
    gap: f64,
    liquid: f64,
    solid: f64,
    neck_radius: Option<f64>,
    bond: u8,
    strength_n: Option<f64>,
    agglomerate: u32,
    broken_at_pa: Option<f64>,
    agglomerate_after: u32,
}

const BRIDGE_COLUMNS: [&str; 13] = [
    "particle_a",
    "particle_b",
    "sx",
    "sy",
    "gap",
    "liquid",
    "solid",
    "neck_radius",
    "bond",
    "strength_n",
    "agglomerate",
    "broken_at_pa",
    "agglomerate_after",
];

/// Writes `bridges.csv`: per pair holding solid, its two particles, the
/// periods b lies from a (`sx`, `sy`), the surface gap, the liquid of its
/// pendular bridge after the drainage, the solid's volume (area in 2D), the
/// solid bridge's neck radius (empty: the solid does not span the gap),
/// whether it is a bond (1), its tensile strength in N (N/m in 2D; empty
/// without a length unit or a bond), the agglomerate it binds (0: none),
/// the agitation's stress in Pa when it broke (empty: intact or no
/// agitation) and the agglomerate it binds after the agitation.
pub fn write_bridges(w: &mut dyn Write, d: &Drying) -> std::io::Result<()> {
    let mut out = csv::Writer::from_writer(w);
    if d.bridges.is_empty() {
        out.write_record(BRIDGE_COLUMNS)
            .map_err(std::io::Error::other)?;
    }
    for b in &d.bridges {
        out.serialize(BridgeLine {
            particle_a: b.particles[0],
            particle_b: b.particles[1],
            sx: b.shift[0],
            sy: b.shift[1],
            gap: b.gap,
            liquid: b.liquid,
            solid: b.solid,
            neck_radius: b.neck_radius,
            bond: u8::from(b.bond),
            strength_n: b.strength,
            agglomerate: b.agglomerate,
            broken_at_pa: b.broken_at,
            agglomerate_after: b.agglomerate_after,
        })
        .map_err(std::io::Error::other)?;
    }
    out.flush()
}

/// A row of `agglomerates.csv`.
#[derive(Serialize)]
struct AgglomerateLine {
    agglomerate: u32,
    particles: u64,
    volume: f64,
    equivalent_diameter: f64,
    bonds: u64,
    weakest_bond_n: Option<f64>,
}

/// Writes `agglomerates.csv`: per agglomerate (largest first), its id (the
/// `agglomerate` of `bridges.csv`), particles, their volume (area in 2D),
/// the diameter of a sphere (disc) of that volume, its bonds and the
/// strength of its weakest bond in N (empty without a length unit).
pub fn write_agglomerates(w: &mut dyn Write, d: &Drying) -> std::io::Result<()> {
    let mut out = csv::Writer::from_writer(w);
    if d.agglomerates.is_empty() {
        out.write_record([
            "agglomerate",
            "particles",
            "volume",
            "equivalent_diameter",
            "bonds",
            "weakest_bond_n",
        ])
        .map_err(std::io::Error::other)?;
    }
    for a in &d.agglomerates {
        out.serialize(AgglomerateLine {
            agglomerate: a.id,
            particles: a.particles,
            volume: a.volume,
            equivalent_diameter: a.equivalent_diameter,
            bonds: a.bonds,
            weakest_bond_n: a.weakest_bond,
        })
        .map_err(std::io::Error::other)?;
    }
    out.flush()
}
