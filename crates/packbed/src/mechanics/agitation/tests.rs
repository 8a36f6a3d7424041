use super::*;
use crate::analysis::pores::drying::{components, AgglomerationSummary, SolidBridge};
use crate::config::Config;
use crate::mechanics::Load;
use crate::pipeline::run_bed;

/// Two touching spheres stacked on the floor of a periodic 10 × 10 box,
/// joined by one solid bridge of neck `a` in a solid of strength `sigma`.
fn stack(a: Real, sigma: Real) -> (Bed<3>, Contacts, Drying) {
    let bed = Bed::of_spheres(
        [10.0, 10.0, 20.0],
        true,
        [([5.0, 5.0, 1.0], 1.0, 0), ([5.0, 5.0, 3.0], 1.0, 0)],
    );
    let contacts = crate::analysis::find_contacts(&bed, 1e-6);
    assert_eq!(contacts.pairs.len(), 1);
    assert_eq!(contacts.walls.len(), 1);
    let drying = Drying {
        summary: AgglomerationSummary {
            tensile_strength: sigma,
            ..AgglomerationSummary::default()
        },
        bridges: vec![SolidBridge {
            particles: [0, 1],
            shift: [0, 0],
            gap: 0.0,
            liquid: 0.0,
            solid: 1e-3,
            neck_radius: Some(a),
            bond: true,
            strength: None,
            agglomerate: 1,
            broken_at: None,
            agglomerate_after: 1,
        }],
        agglomerates: Vec::new(),
        agglomerate_of: vec![1, 1],
        slab: (0.0, 4.0),
    };
    (bed, contacts, drying)
}

/// The stacked pair under compression: the bridge carries the whole load,
/// so it breaks at `σ π a² / A` (A = 100, the box's cross-section), not
/// below; under gravity it carries the top sphere's weight, half the load.
#[test]
fn a_loaded_bridge_breaks_at_its_strength_over_its_share_of_the_load() {
    let (a, sigma) = (0.2, 1e6);
    let strength = sigma * std::f64::consts::PI * a * a;
    for (load, share) in [(Load::Compression, 1.0), (Load::Gravity, 0.5)] {
        let expected = strength / (100.0 * share);
        for (factor, breaks) in [(0.99, false), (1.01, true)] {
            let (bed, contacts, mut drying) = stack(a, sigma);
            let options = AgitationConfig {
                load,
                stress: factor * expected,
                ..AgitationConfig::default()
            };
            agitate(&bed, &contacts, &mut drying, &options).unwrap();
            let s = drying.summary.agitation.as_ref().unwrap();
            let first = s.first_break_stress.unwrap();
            assert!(
                (first - expected).abs() < 1e-6 * expected,
                "{load:?}: {first} vs {expected}"
            );
            assert_eq!(s.bonds, 1);
            assert_eq!(s.broken, u64::from(breaks), "{load:?} at {factor}");
            assert_eq!(s.agglomerates, u64::from(!breaks));
            let b = &drying.bridges[0];
            assert_eq!(b.broken_at.is_some(), breaks);
            assert_eq!(b.agglomerate_after, u32::from(!breaks));
            if breaks {
                assert!((b.broken_at.unwrap() - expected).abs() < 1e-6 * expected);
            }
        }
    }
}

fn agitated(stress: Real) -> (Bed<3>, crate::analysis::pores::drying::Drying) {
    let text = format!(
        "dim = 3\nseed = 11\n[box]\nwidth = 8\ndepth = 8\nheight = 400\nperiodic = true\n\
         [fill]\ncount = 700\n[[species]]\nradius = 1.0\n\
         [analysis]\nmeasures = [\"agglomeration\"]\n\
         [analysis.drying.agitation]\nload = \"shear\"\nstress = {stress}\n"
    );
    let config = Config::from_toml(&text, "test").unwrap();
    let run = run_bed(&config, &mut |_| {}).unwrap();
    let bed = match run.bed {
        crate::bed::AnyBed::D3(b) => b,
        crate::bed::AnyBed::D2(_) => unreachable!(),
    };
    let dried = run.summary.analysis.dried.clone().expect("a dried cake");
    (bed, (*dried).clone())
}

/// Breakage only removes bonds: every agglomerate after the agitation lies
/// inside one before it, the agglomerates after are the components of the
/// bonds left (brute force), and a harder agitation breaks the same bridges
/// at the same stresses and then more (the ramp is one sequence).
#[test]
fn breakage_never_joins_agglomerates() {
    let (bed, weak) = agitated(0.0);
    let s = weak.summary.agitation.clone().unwrap();
    assert_eq!(s.broken, 0);
    assert_eq!(s.agglomerates, weak.summary.agglomerates);
    let first = s.first_break_stress.expect("a loaded bond");
    assert!(first > 0.0);
    let mut before: Option<Drying> = None;
    for factor in [3.0, 30.0] {
        let (_, d) = agitated(factor * first);
        let s = d.summary.agitation.clone().unwrap();
        assert!(s.broken > 0 && s.complete, "{factor}: {s:?}");
        for b in &d.bridges {
            if let Some(at) = b.broken_at {
                assert!(b.bond && at <= factor * first && at >= first * (1.0 - 1e-9));
            }
        }
        // After ⊆ before: particles together after were together before.
        let left: Vec<(u32, u32)> = d
            .bridges
            .iter()
            .filter(|b| b.bond && b.broken_at.is_none())
            .map(|b| (b.particles[0], b.particles[1]))
            .collect();
        let after = components(bed.len(), &left);
        let all: Vec<(u32, u32)> = d
            .bridges
            .iter()
            .filter(|b| b.bond)
            .map(|b| (b.particles[0], b.particles[1]))
            .collect();
        let start = components(bed.len(), &all);
        for p in 0..bed.len() {
            for q in (p + 1..bed.len()).step_by(5) {
                if after[p] == after[q] {
                    assert_eq!(start[p], start[q], "{p} {q} joined");
                }
            }
        }
        let groups = (0..bed.len())
            .filter(|&p| {
                after[p] == p as u32 && after.iter().filter(|&&r| r == p as u32).count() >= 2
            })
            .count() as u64;
        assert_eq!(s.agglomerates, groups);
        assert!(s.agglomerates >= 1 || s.fraction_in_agglomerates == 0.0);
        // The same ramp: what broke under the softer agitation broke here at
        // the same stress.
        if let Some(soft) = &before {
            for (x, y) in soft.bridges.iter().zip(&d.bridges) {
                if let Some(at) = x.broken_at {
                    assert_eq!(y.broken_at, Some(at));
                }
            }
            assert!(s.broken >= soft.summary.agitation.as_ref().unwrap().broken);
        }
        before = Some(d);
    }
}

/// Sheared, the stacked pair fails when its one bridge breaks: the top
/// sphere's load has nowhere to go, and the failure stress is the break's.
#[test]
fn a_cake_whose_last_path_breaks_fails_at_that_stress() {
    let (bed, contacts, mut drying) = stack(0.2, 1e6);
    let options = AgitationConfig {
        load: Load::Shear,
        stress: 1e12,
        ..AgitationConfig::default()
    };
    agitate(&bed, &contacts, &mut drying, &options).unwrap();
    let s = drying.summary.agitation.unwrap();
    assert_eq!(s.broken, 1);
    assert_eq!(s.failure_stress, s.first_break_stress);
    assert!(s.failure_stress.unwrap() < 1e12);
    assert_eq!(s.agglomerates, 0);
}
