//! Ensemble throughput: 500 replicates of the source study's 3D box with radii
//! 10 and 20 (ratio 1:1), on all cores, writing one `summary.json` per replicate
//! and the statistics files (target: at most 2 s wall on 2 cores).

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use packbed::Config;
use packbed::{EnsembleOptions, Shard};

fn ensemble_500(cr: &mut Criterion) {
    let mut c = Config::default();
    c.species[0].radius = Some(10.0);
    c.species[1].radius = Some(20.0);
    let opts = EnsembleOptions {
        runs: 500,
        jobs: None,
        shard: Shard::ALL,
        keep_beds: false,
        pictures: true,
        stop: None,
    };
    let root = tempfile::tempdir().expect("temporary directory");
    let mut k = 0u32;
    let mut group = cr.benchmark_group("ensemble");
    group.sample_size(10);
    group.throughput(Throughput::Elements(opts.runs));
    group.bench_function("3d-thesis-10-20-x500", |b| {
        b.iter(|| {
            // A fresh directory each time: a reused one would resume, not build.
            k += 1;
            let out = root.path().join(format!("e{k}"));
            packbed::run_ensemble(&c, &opts, &out, &|_| {}).expect("valid config")
        })
    });
    group.finish();
}

criterion_group!(benches, ensemble_500);
criterion_main!(benches);
