//! Agitation of the dried cake: its solid bridges break, the weakest for
//! the load they carry first, and its agglomerates split.
//!
//! The dried cake is the bed as [`crate::mechanics`] loads it (`shear`,
//! `compression`, `gravity`; rigid bodies, linear springs), with one change:
//! a contact holding a solid bridge that is a bond ([`Drying::bridges`]) is
//! a bond of tensile strength `σ_t π a²` (`σ_t 2a` per unit depth in 2D;
//! a bridge across a gap is a bond too), while the contacts without one
//! and the walls carry their share of the load and never break (dry
//! contacts of hard particles; an agitated dryer shears the product, it
//! does not mill it).
//!
//! The load is raised quasi-statically up to the agitation's stress `τ`
//! (its total over the bed's cross-section). With the forces per unit load
//! `f_k` of the current network, bond `k` breaks at the stress
//! `τ_k = S_k / (A |f_k|)`; the bond of least `τ_k` breaks first, the bed is
//! solved again, and so on until every bond left bears `τ` (the stress of
//! each break is the ramp's, the largest `τ_k` so far, since the load never
//! falls). The breakage stops at `τ`, or where the cake fails: a loaded
//! piece keeps no path through bonds to the floor or a wall (as `packbed
//! fragment` defines failure) or a piece turns mechanism, the ground
//! springs that hold mechanisms bearing more than 1 % of the load; its
//! stress is the cake's strength under that load. Breaking only removes bonds, so an agglomerate after the
//! agitation lies inside one before it (tests).

use super::network::{self, Bodies};
use super::{bond_counts, bond_forces, bonded, loads, network_state, solver, unbond};
use crate::analysis::pores::drying::{product, AgitationSummary, Drying};
use crate::analysis::{Contact, Contacts};
use crate::bed::Bed;
use crate::config::AgitationConfig;
use crate::error::{Error, Result};
use crate::math::Real;
use std::collections::HashMap;

/// The share of the load the ground springs carry when the cake has failed:
/// an intact cake leaves them ~1e-6 of it, a failed one nearly all.
const FAILED: Real = 1e-2;

/// The force the ground springs carry, summed over bodies, over the load's
/// total.
fn ground_share<const D: usize>(u: &[Real], ground: &[Real]) -> Real {
    let m = super::spring::body_dofs(D);
    (0..u.len() / m)
        .map(|b| {
            (0..D)
                .map(|c| (ground[b * m + c] * u[b * m + c]).powi(2))
                .sum::<Real>()
                .sqrt()
        })
        .sum::<Real>()
        / super::TOTAL
}

/// Agitates the dried cake `drying` of `bed` (`contacts`: the analysis'
/// contacts of `bed`) as `options` say: marks each broken bridge with the
/// stress it broke at, names the agglomerates after it and fills
/// `drying.summary.agitation`.
pub fn agitate<const D: usize>(
    bed: &Bed<D>,
    contacts: &Contacts,
    drying: &mut Drying,
    options: &AgitationConfig,
) -> Result<()> {
    if let Some(why) = options.problem() {
        return Err(Error::config(format!("analysis.{why}")));
    }
    // The network: every contact, and the bond bridges across a gap.
    let key = |a: u32, b: u32| (a.min(b), a.max(b));
    let mut bridge_at: HashMap<(u32, u32), usize> = HashMap::new();
    for (k, b) in drying.bridges.iter().enumerate() {
        let [p, q] = b.particles;
        if b.bond && bed.bodies[p as usize] != bed.bodies[q as usize] {
            bridge_at.entry(key(p, q)).or_insert(k);
        }
    }
    let mut pairs = contacts.pairs.clone();
    let touching: std::collections::HashSet<(u32, u32)> =
        pairs.iter().map(|c| key(c.i, c.j)).collect();
    let mut across: Vec<(&(u32, u32), &usize)> = bridge_at
        .iter()
        .filter(|(pq, _)| !touching.contains(pq))
        .collect();
    across.sort_by_key(|x| *x.1);
    for (&(i, j), &k) in across {
        pairs.push(Contact {
            i,
            j,
            gap: drying.bridges[k].gap,
        });
    }
    let net = Contacts {
        pairs,
        walls: contacts.walls.clone(),
    };
    let bodies = Bodies::of(bed);
    let bonds = network::bonds(bed, &bodies, &net);
    // Each bond's bridge and strength (Pa × area of a length unit²).
    let sigma = drying.summary.tensile_strength;
    let bridge_of: Vec<Option<usize>> = bonds
        .iter()
        .map(|g| {
            let j = g.bead_j?;
            bridge_at.get(&key(g.bead_i, j)).copied()
        })
        .collect();
    let strength: Vec<Real> = bridge_of
        .iter()
        .map(|b| match b.and_then(|k| drying.bridges[k].neck_radius) {
            Some(a) if D == 3 => sigma * std::f64::consts::PI * a * a,
            Some(a) => sigma * 2.0 * a,
            None => Real::INFINITY,
        })
        .collect();
    let area: Real = (0..D - 1).map(|k| bed.container.extent(k)).product();

    let load_groups = loads::Loads::new(options.load, bed, &bodies, &bonds)?;
    let springs = solver::Springs {
        kn: 1.0,
        kt: options.kt_over_kn,
    };
    let nb = bodies.len();
    let mut bond_count = bond_counts(&bonds, nb);
    let mut loaded = load_groups
        .current(&bonded(&bond_count))
        .ok_or_else(|| load_groups.unbonded(&bonded(&bond_count)))?;
    let mut system = solver::Solver::new(&bonds, &bodies.reference, &bodies.reach, springs)?;
    let mut alive = vec![true; bonds.len()];
    let mut ramp: Real = 0.0;
    let mut first = None;
    let mut broken = 0u64;
    let mut complete = true;
    let mut failure = None;
    loop {
        let u = system.solve(&loads::load_vector(&loaded, nb))?;
        // Past a break that leaves the load to the ground springs (a piece
        // turned mechanism), the cake has failed.
        if broken > 0 && ground_share::<D>(&u, system.ground()) > FAILED {
            failure = Some(ramp);
            break;
        }
        let f = bond_forces(&bonds, &alive, &u, springs);
        // The bond that breaks at the least stress; the first listed of a tie.
        let weakest = (0..bonds.len())
            .filter(|&k| alive[k] && strength[k].is_finite())
            .map(|k| (k, strength[k] / (area * f[k].norm())))
            .filter(|(_, t)| t.is_finite())
            .reduce(|a, b| if b.1 < a.1 * (1.0 - super::TIE) { b } else { a });
        let Some((k, at)) = weakest else { break };
        first.get_or_insert(at);
        if at > options.stress {
            break;
        }
        if broken >= options.max_breaks {
            complete = false;
            break;
        }
        ramp = ramp.max(at);
        if let Some(b) = bridge_of[k] {
            drying.bridges[b].broken_at = Some(ramp);
        }
        broken += 1;
        alive[k] = false;
        unbond(&mut bond_count, &bonds[k]);
        system.remove(k)?;
        // The cake fails when a loaded piece loses its last path to the
        // floor or walls: past it, the quasi-static load has no equilibrium.
        let now = load_groups.current(&bonded(&bond_count));
        let (_, _, failed) = network_state(&bonds, &alive, nb, now.as_deref());
        match now {
            Some(now) if !failed => loaded = now,
            _ => {
                failure = Some(ramp);
                break;
            }
        }
    }

    // The product after it: the agglomerates of the bonds left.
    let left: Vec<(u32, u32)> = drying
        .bridges
        .iter()
        .filter(|b| b.bond && b.broken_at.is_none())
        .map(|b| (b.particles[0], b.particles[1]))
        .collect();
    let after = product(bed, drying.slab, &left);
    for b in &mut drying.bridges {
        b.agglomerate_after = if b.bond && b.broken_at.is_none() {
            after.agglomerate_of[b.particles[0] as usize]
        } else {
            0
        };
    }
    drying.summary.agitation = Some(AgitationSummary {
        load: options.load.name().into(),
        stress: options.stress,
        bonds: strength.iter().filter(|s| s.is_finite()).count() as u64,
        broken,
        first_break_stress: first,
        failure_stress: failure,
        complete,
        agglomerates: after.agglomerates.len() as u64,
        fraction_in_agglomerates: after.fraction_in_agglomerates,
        mean_particles: after.mean_particles,
        largest_particles: after.largest_particles,
        d50_product: after.d50_product,
        volume_by_particles: after.volume_by_particles,
    });
    Ok(())
}

#[cfg(test)]
mod tests;
