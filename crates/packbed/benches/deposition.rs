//! Deposition throughput (particles per second) on periodic beds; the figures of
//! BENCHMARKS.md come from `packbed bench` (10^6 particles) and from this.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use packbed::bench::{BenchBed, BenchSizes};
use packbed::build;
use packbed::{BaseLayerKind, Config, SpeciesConfig};

/// Equal spheres (or discs) of radius 10, or two sizes, in a periodic box about
/// as high as the bed grows.
fn config(dim: u8, n: u64, radii: &[f64]) -> Config {
    let mut c = Config {
        dim,
        ..Config::default()
    };
    let template = c.species[0].clone();
    c.species = radii
        .iter()
        .map(|&r| SpeciesConfig {
            radius: Some(r),
            ..template.clone()
        })
        .collect();
    let diameters = (n as f64).powf(1.0 / dim as f64).max(4.0).round();
    c.container.preset = None;
    c.container.diameters = Some(diameters);
    c.container.periodic = true;
    c.fill.count = Some(n);
    c.fill.base_layer = BaseLayerKind::None;
    c
}

fn deposition(cr: &mut Criterion) {
    let mut group = cr.benchmark_group("deposition");
    group.sample_size(10);
    for (name, dim, n, radii) in [
        ("3d-equal", 3u8, 50_000u64, &[10.0][..]),
        ("2d-equal", 2, 100_000, &[10.0][..]),
        ("3d-10-50", 3, 20_000, &[10.0, 50.0][..]),
    ] {
        let c = config(dim, n, radii);
        group.throughput(Throughput::Elements(n));
        group.bench_with_input(BenchmarkId::new(name, n), &c, |b, c| {
            b.iter(|| build(c, &mut |_| std::ops::ControlFlow::Continue(())).expect("valid config"))
        });
    }
    // Broad lognormal powders (median 10, default ±3 sd truncation) on the
    // bench bed of `packbed bench --gsd`: the multilevel grid's rows.
    for gsd in [1.6, 2.0] {
        let n = 20_000;
        let c = BenchBed {
            dim: 3,
            n,
            chains: None,
            periodic: true,
            sizes: BenchSizes::Lognormal(gsd),
            base_layer: false,
            contacts: None,
            sticking: None,
            friction_angle: None,
            restitution: None,
            drop_height: None,
            sliding_friction: None,
            climb_over: false,
        }
        .config();
        group.throughput(Throughput::Elements(n));
        group.bench_with_input(
            BenchmarkId::new(format!("3d-lognormal-gsd{gsd}"), n),
            &c,
            |b, c| {
                b.iter(|| {
                    build(c, &mut |_| std::ops::ControlFlow::Continue(())).expect("valid config")
                })
            },
        );
    }
    group.finish();
}

/// Five-bead chains of radius 10 in a periodic box, entering at random: 20,000
/// in 2D (width 3000), 10,000 in 3D (400 × 400), the chains/s rows of
/// docs/history/benchmarks.md ("Chains").
fn chains(cr: &mut Criterion) {
    let mut group = cr.benchmark_group("deposition-chains");
    group.sample_size(10);
    for (dim, n, w) in [(2u8, 20_000u64, 3000.0), (3, 10_000, 400.0)] {
        let text = format!(
            "dim = {dim}\nseed = 1\n[box]\nwidth = {w}\nheight = 100000\nperiodic = true\n\
             [fill]\ncount = {}\nbase_layer = \"none\"\n\
             [[species]]\nradius = 10\nshape = \"chain\"\nbeads = 5\n",
            5 * n
        );
        let c = Config::from_toml(&text, "bench").expect("valid config");
        group.throughput(Throughput::Elements(n));
        group.bench_with_input(
            BenchmarkId::new(format!("{dim}d-5-beads"), n),
            &c,
            |b, c| {
                b.iter(|| {
                    build(c, &mut |_| std::ops::ControlFlow::Continue(())).expect("valid config")
                })
            },
        );
    }
    group.finish();
}

criterion_group!(benches, deposition, chains);
criterion_main!(benches);
