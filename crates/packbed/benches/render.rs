//! Rendering throughput: 10^6 spheres to a 1600 × 1200 PNG (target: under 10 s).

use criterion::{criterion_group, criterion_main, Criterion};
use packbed::render::{render_png, RenderOptions};
use packbed::Container;
use packbed::Vector;
use packbed::{AnyBed, Bed};

/// A simple cubic lattice of touching spheres, 100 × 100 × 100 = 10^6 (the
/// renderer's cost depends on the projected sizes, not on how they were packed).
fn lattice(n: usize) -> Bed<3> {
    let s = n as f64 * 2.0;
    let mut bed = Bed::new(
        Container {
            size: Vector([s, s, s]),
            periodic: false,
        },
        Vec::new(),
    );
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let c = Vector([
                    1.0 + 2.0 * i as f64,
                    1.0 + 2.0 * j as f64,
                    1.0 + 2.0 * k as f64,
                ]);
                bed.push(c, 1.0, ((i + j + k) % 2) as u32);
            }
        }
    }
    bed
}

fn render(c: &mut Criterion) {
    let bed = AnyBed::D3(lattice(100));
    let opts = RenderOptions {
        width: 1600,
        height: 1200,
        ..RenderOptions::default()
    };
    let mut g = c.benchmark_group("render");
    g.sample_size(10);
    g.bench_function("3d_1e6_spheres_1600x1200_png", |b| {
        b.iter(|| render_png(&bed, &opts).unwrap())
    });
    g.finish();
}

criterion_group!(benches, render);
criterion_main!(benches);
