//! Analysis speed on a bed of 10^6 spheres (radii 10 and 20, 1:1, walls): contacts
//! and coordination, packing (global, bulk, regions, profile), and percolation
//! (graph, clusters, BFS, disjoint chains; the capped unique-chain enumeration is
//! left out, as the target says). Figures in BENCHMARKS.md.

use criterion::{criterion_group, criterion_main, Criterion};
use packbed::build;
use packbed::AnyBed;
use packbed::{bulk_region, coordination, find_contacts, profile, regional_packing};
use packbed::{global_fraction, particle_volumes};
use packbed::{percolation, PercolationOptions};
use packbed::{Config, SpeciesConfig};
use std::hint::black_box;

fn bed_config(n: u64) -> Config {
    let mut c = Config::default();
    let template = c.species[0].clone();
    c.species = [20.0, 10.0]
        .iter()
        .map(|&r| SpeciesConfig {
            radius: Some(r),
            ..template.clone()
        })
        .collect();
    // About as high as wide: ~3.1e4 volume units per particle at 0.6 packing.
    let side = (n as f64 * 3.1e4).cbrt();
    c.container.preset = None;
    c.container.diameters = Some((side / 40.0).round());
    c.fill.count = Some(n);
    c
}

fn analysis(cr: &mut Criterion) {
    let n: u64 = std::env::var("PACKBED_BENCH_N")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1_000_000);
    let (bed, _) =
        build(&bed_config(n), &mut |_| std::ops::ControlFlow::Continue(())).expect("valid config");
    let AnyBed::D3(bed) = bed else {
        unreachable!("3D config")
    };
    let mut group = cr.benchmark_group("analysis");
    group.sample_size(10);
    let no_enumeration = PercolationOptions {
        max_chains: 0,
        ..Default::default()
    };
    group.bench_function(format!("contacts-packing-percolation/{n}"), |b| {
        b.iter(|| {
            let contacts = find_contacts(&bed, 1e-6);
            let z = coordination(&bed, &contacts);
            let volumes = particle_volumes(&bed);
            let global = global_fraction(&bed);
            let bulk = bulk_region(&bed).map(|r| r.fraction(&bed));
            let regional = regional_packing(&bed);
            let prof = profile(&bed, 10.0);
            let perc = percolation(&bed, &contacts, &no_enumeration);
            black_box((z, volumes, global, bulk, regional, prof, perc))
        })
    });
    let contacts = find_contacts(&bed, 1e-6);
    group.bench_function(format!("contacts/{n}"), |b| {
        b.iter(|| black_box(find_contacts(&bed, 1e-6)))
    });
    group.bench_function(format!("percolation/{n}"), |b| {
        b.iter(|| black_box(percolation(&bed, &contacts, &no_enumeration)))
    });
    group.bench_function(format!("unique-chains-capped/{n}"), |b| {
        b.iter(|| black_box(percolation(&bed, &contacts, &PercolationOptions::default())))
    });
    group.finish();
}

criterion_group!(benches, analysis);
criterion_main!(benches);
