//! The analysis suite on deposited beds: cross-checks against independent brute
//! force (a raster of the pore space for the voids) and identities between the
//! measures.

use crate::common::{config, run};
use packbed::Bed;
use packbed::{analyze_with, find_contacts, voids, AnalysisOptions};
use std::f64::consts::PI;

/// `count` discs of the given radii (equal ratios) in the default box.
fn bed2(count: u64, radii: &[f64], periodic: bool, seed: u64) -> Bed<2> {
    let species: String = radii
        .iter()
        .map(|r| format!("[[species]]\nradius = {r:?}\n"))
        .collect();
    let c = config(&format!(
        "dim = 2\nseed = {seed}\n[box]\nperiodic = {periodic}\n[fill]\ncount = {count}\n{species}"
    ));
    run::<2>(&c).0
}

/// Areas of the connected pieces of pore space on a pixel grid, leaving out the
/// piece open to the top. Pixels within a pixel of a contact point are treated
/// as solid so that the raster cannot leak between touching discs.
fn raster_voids(bed: &Bed<2>, h: f64) -> Vec<f64> {
    let w = bed.container.size[0];
    let top = bed.container.size[1].max(bed.top());
    let (nx, ny) = ((w / h).ceil() as usize, (top / h).ceil() as usize + 1);
    let mut solid = vec![false; nx * ny];
    let contacts = find_contacts(bed, 1e-6);
    let mark = |cx: f64, cy: f64, r: f64, solid: &mut Vec<bool>| {
        let (i0, i1) = (((cx - r) / h).floor() as i64, ((cx + r) / h).ceil() as i64);
        let (j0, j1) = (((cy - r) / h).floor() as i64, ((cy + r) / h).ceil() as i64);
        for j in j0.max(0)..=j1.min(ny as i64 - 1) {
            for i in i0..=i1 {
                let (x, y) = ((i as f64 + 0.5) * h, (j as f64 + 0.5) * h);
                if (x - cx).powi(2) + (y - cy).powi(2) <= r * r {
                    let ii = i.rem_euclid(nx as i64) as usize;
                    if bed.container.periodic || (0..nx as i64).contains(&i) {
                        solid[j as usize * nx + ii] = true;
                    }
                }
            }
        }
    };
    for (c, &r) in bed.centres.iter().zip(&bed.radii) {
        mark(c[0], c[1], r, &mut solid);
    }
    for p in &contacts.pairs {
        let (a, b) = (bed.centres[p.i as usize], bed.centres[p.j as usize]);
        let d = bed.container.displacement(&a, &b);
        let t = bed.radii[p.i as usize] / (bed.radii[p.i as usize] + bed.radii[p.j as usize]);
        mark(a[0] + t * d[0], a[1] + t * d[1], 1.5 * h, &mut solid);
    }
    for wc in &contacts.walls {
        let c = bed.centres[wc.i as usize];
        let p = match wc.wall.name() {
            "floor" => (c[0], 0.0),
            "x0" => (0.0, c[1]),
            _ => (w, c[1]),
        };
        mark(p.0, p.1, 1.5 * h, &mut solid);
    }
    // Flood fill, 4-connected.
    let mut label = vec![usize::MAX; nx * ny];
    let mut areas = Vec::new();
    for s in 0..nx * ny {
        if solid[s] || label[s] != usize::MAX {
            continue;
        }
        let id = areas.len();
        let (mut count, mut open) = (0usize, false);
        let mut stack = vec![s];
        label[s] = id;
        while let Some(k) = stack.pop() {
            count += 1;
            let (i, j) = (k % nx, k / nx);
            open |= j == ny - 1;
            let mut nb = Vec::with_capacity(4);
            if i > 0 {
                nb.push(k - 1);
            } else if bed.container.periodic {
                nb.push(k + nx - 1);
            }
            if i + 1 < nx {
                nb.push(k + 1);
            } else if bed.container.periodic {
                nb.push(k + 1 - nx);
            }
            if j > 0 {
                nb.push(k - nx);
            }
            if j + 1 < ny {
                nb.push(k + nx);
            }
            for q in nb {
                if !solid[q] && label[q] == usize::MAX {
                    label[q] = id;
                    stack.push(q);
                }
            }
        }
        areas.push(if open { -1.0 } else { count as f64 * h * h });
    }
    areas.retain(|&a| a >= 0.0);
    areas
}

#[test]
fn voids_agree_with_a_raster_of_the_pore_space() {
    for (periodic, seed) in [(false, 3), (true, 4)] {
        let bed = bed2(150, &[10.0, 20.0], periodic, seed);
        let v = voids(&bed, &find_contacts(&bed, 1e-6));
        let h = 0.1;
        let mut raster = raster_voids(&bed, h);
        let mut exact: Vec<f64> = v.iter().map(|v| v.area).collect();
        raster.sort_by(f64::total_cmp);
        exact.sort_by(f64::total_cmp);
        // The raster loses tiny voids (below a few pixels) entirely; compare the
        // rest one to one.
        let big: Vec<f64> = exact.iter().copied().filter(|&a| a > 2.0).collect();
        let rbig: Vec<f64> = raster.iter().copied().filter(|&a| a > 2.0).collect();
        assert_eq!(
            big.len(),
            rbig.len(),
            "periodic {periodic}: {big:?} vs {rbig:?}"
        );
        for (a, b) in big.iter().zip(&rbig) {
            // Pixel error along the perimeter, plus the plugged contact points.
            assert!((a - b).abs() < 0.03 * a + 2.0, "{a} vs {b}");
        }
    }
}

#[test]
fn measures_fit_together_on_deposited_beds() {
    for periodic in [false, true] {
        let bed = bed2(600, &[10.0, 20.0], periodic, 7);
        let (contacts, s) = analyze_with(&bed, &AnalysisOptions::default());
        // Histograms count every body once; the mean is their mean.
        let k = s.coordination.as_ref().unwrap();
        let bodies: u64 = k.histogram.iter().sum();
        assert_eq!(bodies as usize, bed.body_count());
        let mean = k
            .histogram
            .iter()
            .enumerate()
            .map(|(z, &c)| z as f64 * c as f64)
            .sum::<f64>()
            / bodies as f64;
        assert!((mean - k.mean).abs() < 1e-12);
        assert_eq!(k.by_species.iter().map(|s| s.bodies).sum::<u64>(), bodies);
        // 2 × contacts = Σ coordination (spheres are bodies).
        assert_eq!(
            2 * contacts.pairs.len() as u64,
            k.histogram
                .iter()
                .enumerate()
                .map(|(z, &c)| z as u64 * c)
                .sum::<u64>()
        );
        // The profile averages to the global packing fraction (slabs tile the box).
        let p = &s.packing.as_ref().unwrap().profile;
        let h = bed.container.size[1].max(bed.top());
        let avg: f64 = p
            .fraction
            .iter()
            .enumerate()
            .map(|(i, f)| {
                let hi = ((i + 1) as f64 * p.slab).min(h);
                f * (hi - i as f64 * p.slab)
            })
            .sum::<f64>()
            / h;
        assert!(
            (avg - s.packing.as_ref().unwrap().global).abs() < 1e-12,
            "{avg} vs {}",
            s.packing.as_ref().unwrap().global
        );
        // Segregation shares add up to one in every slab with solid.
        for k in 0..s.segregation.as_ref().unwrap().z.len() {
            let t: f64 = s
                .segregation
                .as_ref()
                .unwrap()
                .composition
                .iter()
                .map(|c| c[k])
                .sum();
            assert!(t == 0.0 || (t - 1.0).abs() < 1e-12);
        }
        // Voids: total pore area below the surface is bounded by the box minus the
        // discs; every void has at least 3 sides.
        let v = s.voids.as_ref().unwrap();
        let discs: f64 = bed.radii.iter().map(|r| PI * r * r).sum();
        let box_area = bed.container.size[0] * h;
        assert!(v.total_area > 0.0 && v.total_area < box_area - discs);
        assert!(v.sides.iter().all(|&n| n >= 3), "{:?}", v.sides_histogram);
        // Percolation numbers are consistent with each other.
        let c = s.percolation.as_ref().unwrap();
        assert_eq!(c.spans, c.shortest_chain.is_some());
        assert_eq!(c.spans, c.disjoint_chains > 0);
        if let (Some(l), Some(sh)) = (c.chain_length, c.shortest_chain) {
            assert!(l.min >= sh);
        }
        let json = serde_json::to_value(&s).unwrap();
        assert!(json.pointer("/packing/regions/centre").is_some());
        assert!(json.pointer("/orientation").is_none());
    }
}
