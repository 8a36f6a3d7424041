use super::*;
use proptest::prelude::*;
use rand::{RngExt, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus as StdRng;
use std::f64::consts::PI;

fn rel_close(a: f64, b: f64, tol: f64) -> bool {
    a == b || (a - b).abs() <= tol * a.abs().max(b.abs())
}

#[track_caller]
fn assert_rel(a: f64, b: f64, tol: f64) {
    assert!(rel_close(a, b, tol), "{a} vs {b} (rel tol {tol})");
}

fn dist3(a: V3, b: V3) -> f64 {
    norm3(sub3(a, b))
}

/// Regular tetrahedron with the given edge, shifted to `origin`.
fn regular_tet(edge: f64, origin: V3) -> [V3; 4] {
    let s = edge / (2.0 * 2f64.sqrt());
    [[1., 1., 1.], [1., -1., -1.], [-1., 1., -1.], [-1., -1., 1.]]
        .map(|v| add3(origin, scale3(v, s)))
}

fn equilateral(edge: f64, origin: V2) -> [V2; 3] {
    [
        [0.0, 0.0],
        [edge, 0.0],
        [0.5 * edge, 0.5 * 3f64.sqrt() * edge],
    ]
    .map(|v| [v[0] + origin[0], v[1] + origin[1]])
}

/// Distance from `x` to the plane through `a, b, c`.
fn plane_dist(x: V3, a: V3, b: V3, c: V3) -> f64 {
    let n = cross3(sub3(b, a), sub3(c, a));
    dot3(n, sub3(x, a)).abs() / norm3(n)
}

/// Distance from `x` to the line through `a, b`.
fn line_dist(x: V2, a: V2, b: V2) -> f64 {
    cross2(sub2(b, a), sub2(x, a)).abs() / norm2(sub2(b, a))
}

// ---- independent numerical solver: Newton with partial pivoting ----

fn gauss_solve<const N: usize>(mut a: [[f64; N]; N], mut b: [f64; N]) -> Option<[f64; N]> {
    for col in 0..N {
        let piv = (col..N).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))?;
        if a[piv][col].abs() < 1e-300 {
            return None;
        }
        a.swap(col, piv);
        b.swap(col, piv);
        for row in col + 1..N {
            let f = a[row][col] / a[col][col];
            let pivot_row = a[col];
            for (ak, pk) in a[row].iter_mut().zip(pivot_row).skip(col) {
                *ak -= f * pk;
            }
            b[row] -= f * b[col];
        }
    }
    let mut x = [0.0; N];
    for row in (0..N).rev() {
        let s: f64 = (row + 1..N).map(|k| a[row][k] * x[k]).sum();
        x[row] = (b[row] - s) / a[row][row];
    }
    Some(x)
}

fn newton<const N: usize>(
    mut z: [f64; N],
    f: impl Fn(&[f64; N]) -> ([f64; N], [[f64; N]; N]),
) -> Option<[f64; N]> {
    for _ in 0..100 {
        let (fz, jac) = f(&z);
        if fz.iter().all(|v| v.abs() < 1e-15) {
            return Some(z);
        }
        let dz = gauss_solve(jac, fz.map(|v| -v))?;
        for (zi, di) in z.iter_mut().zip(dz) {
            *zi += di;
        }
    }
    let (fz, _) = f(&z);
    fz.iter().all(|v| v.abs() < 1e-12).then_some(z)
}

/// Tangent sphere by Newton on `|x − c_i| − r_i − ρ = 0`, started at the
/// vertex centroid, independent of the closed form.
fn newton_tangent_3d(c: &[V3; 4], r: &[f64; 4]) -> Option<f64> {
    let g = scale3(c.iter().fold([0.0; 3], |s, x| add3(s, *x)), 0.25);
    let rho0 = (0..4).map(|i| dist3(g, c[i]) - r[i]).sum::<f64>() / 4.0;
    let z = newton([g[0], g[1], g[2], rho0], |z| {
        let x = [z[0], z[1], z[2]];
        let mut fz = [0.0; 4];
        let mut j = [[0.0; 4]; 4];
        for i in 0..4 {
            let dv = sub3(x, c[i]);
            let n = norm3(dv);
            fz[i] = n - r[i] - z[3];
            j[i] = [dv[0] / n, dv[1] / n, dv[2] / n, -1.0];
        }
        (fz, j)
    })?;
    Some(z[3])
}

fn newton_tangent_2d(c: &[V2; 3], r: &[f64; 3]) -> Option<f64> {
    let g = [
        (c[0][0] + c[1][0] + c[2][0]) / 3.0,
        (c[0][1] + c[1][1] + c[2][1]) / 3.0,
    ];
    let rho0 = (0..3).map(|i| norm2(sub2(g, c[i])) - r[i]).sum::<f64>() / 3.0;
    let z = newton([g[0], g[1], rho0], |z| {
        let mut fz = [0.0; 3];
        let mut j = [[0.0; 3]; 3];
        for i in 0..3 {
            let dv = sub2([z[0], z[1]], c[i]);
            let n = norm2(dv);
            fz[i] = n - r[i] - z[2];
            j[i] = [dv[0] / n, dv[1] / n, -1.0];
        }
        (fz, j)
    })?;
    Some(z[2])
}

/// Constriction by Newton in 3D: three tangency equations plus the
/// facet-plane equation.
fn newton_constriction_3d(c: &[V3; 3], r: &[f64; 3]) -> Option<f64> {
    let g = scale3(add3(add3(c[0], c[1]), c[2]), 1.0 / 3.0);
    let n = cross3(sub3(c[1], c[0]), sub3(c[2], c[0]));
    let rho0 = (0..3).map(|i| dist3(g, c[i]) - r[i]).sum::<f64>() / 3.0;
    let z = newton([g[0], g[1], g[2], rho0], |z| {
        let x = [z[0], z[1], z[2]];
        let mut fz = [0.0; 4];
        let mut j = [[0.0; 4]; 4];
        for i in 0..3 {
            let dv = sub3(x, c[i]);
            let m = norm3(dv);
            fz[i] = m - r[i] - z[3];
            j[i] = [dv[0] / m, dv[1] / m, dv[2] / m, -1.0];
        }
        fz[3] = dot3(n, sub3(x, c[0]));
        j[3] = [n[0], n[1], n[2], 0.0];
        (fz, j)
    })?;
    Some(z[3])
}

// ---- random well-shaped cells ----

/// Perturbed regular tetrahedron (edge ≈ 1) with non-overlapping radii:
/// each radius is a fraction `f_i` of half its nearest-neighbour distance.
fn tet_cell(pert: &[f64], f: &[f64], origin: V3) -> ([V3; 4], [f64; 4]) {
    let mut c = regular_tet(1.0, origin);
    for (i, ci) in c.iter_mut().enumerate() {
        *ci = add3(*ci, [pert[3 * i], pert[3 * i + 1], pert[3 * i + 2]]);
    }
    let mut r = [0.0; 4];
    for i in 0..4 {
        let m = (0..4)
            .filter(|&j| j != i)
            .map(|j| dist3(c[i], c[j]))
            .fold(f64::INFINITY, f64::min);
        r[i] = f[i] * 0.5 * m;
    }
    (c, r)
}

fn tri_cell(pert: &[f64], f: &[f64], origin: V2) -> ([V2; 3], [f64; 3]) {
    let mut c = equilateral(1.0, origin);
    for (i, ci) in c.iter_mut().enumerate() {
        *ci = [ci[0] + pert[2 * i], ci[1] + pert[2 * i + 1]];
    }
    let mut r = [0.0; 3];
    for i in 0..3 {
        let m = (0..3)
            .filter(|&j| j != i)
            .map(|j| norm2(sub2(c[i], c[j])))
            .fold(f64::INFINITY, f64::min);
        r[i] = f[i] * 0.5 * m;
    }
    (c, r)
}

// ---- hand-solved cases ----

#[test]
fn regular_tet_of_touching_spheres_pore_radius() {
    for &r in &[1.0, 0.37, 2.5e3] {
        let c = regular_tet(2.0 * r, [3.0, -1.0, 0.5]);
        assert_rel(
            pore_body_radius_3d(&c, &[r; 4]),
            r * (1.5f64.sqrt() - 1.0),
            1e-13,
        );
    }
}

#[test]
fn touching_circles_constriction_in_tilted_plane() {
    let r = 0.8;
    let t = equilateral(2.0 * r, [0.0, 0.0]);
    // Embed in a tilted plane through an arbitrary point.
    let e1 = scale3([1.0, 2.0, -0.5], 1.0 / norm3([1.0, 2.0, -0.5]));
    let e2u = cross3(e1, [0.3, -0.2, 1.0]);
    let e2 = scale3(e2u, 1.0 / norm3(e2u));
    let c = t.map(|p| add3([1.0, 5.0, -2.0], add3(scale3(e1, p[0]), scale3(e2, p[1]))));
    let want = r * (2.0 / 3f64.sqrt() - 1.0);
    assert_rel(constriction_radius_3d(&c, &[r; 3]), want, 1e-13);
}

#[test]
fn touching_discs_pore_radius_2d() {
    let r = 1.7;
    let c = equilateral(2.0 * r, [-4.0, 9.0]);
    assert_rel(
        pore_body_radius_2d(&c, &[r; 3]),
        r * (2.0 / 3f64.sqrt() - 1.0),
        1e-13,
    );
}

#[test]
fn equal_weights_power_centre_is_circumcentre() {
    let c = regular_tet(2.0, [1.0, 2.0, 3.0]);
    let (p, pw) = power_centre_3d(&c, &[0.4; 4]).unwrap();
    for (pi, want) in p.iter().zip([1.0, 2.0, 3.0]) {
        assert!((pi - want).abs() < 1e-14);
    }
    // Circumradius of the regular tetrahedron: edge·√(3/8).
    assert_rel(pw, 1.5 - 0.16, 1e-13);

    let t = equilateral(3.0, [1.0, -1.0]);
    let (p2, pw2) = power_centre_2d(&t, &[0.7; 3]).unwrap();
    assert!((p2[0] - 2.5).abs() < 1e-14 && (p2[1] - (-1.0 + 3f64.sqrt() / 2.0)).abs() < 1e-14);
    assert_rel(pw2, 3.0 - 0.49, 1e-13);
}

#[test]
fn regular_tet_volume_and_void_closed_form() {
    let a = 1.3;
    let cv = cell_volumes_3d(&regular_tet(a, [0.2, 0.1, -7.0]), &[a / 2.0; 4]);
    let vol = a.powi(3) / (6.0 * 2f64.sqrt());
    // Vertex solid angle of the regular tetrahedron: arccos(23/27).
    let sectors = 4.0 * (a / 2.0).powi(3) * (23.0f64 / 27.0).acos() / 3.0;
    assert_rel(cv.volume, vol, 1e-13);
    assert_rel(cv.void_volume, vol - sectors, 1e-12);
    assert!(!cv.clamped);
}

#[test]
fn constriction_2d_is_half_gap() {
    let c = [[0.0, 1.0], [3.0, 5.0]];
    assert_rel(constriction_radius_2d(&c, &[1.0, 2.5]), 0.75, 1e-15);
    assert_eq!(constriction_radius_2d(&c, &[2.5, 2.5]), 0.0);
    assert_eq!(constriction_radius_2d(&c, &[3.0, 2.5]), 0.0);
}

#[test]
fn zero_radii_reduce_to_plain_geometry() {
    let c = [
        [0.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [0.0, 3.0, 0.0],
        [0.0, 0.0, 4.0],
    ];
    // Circumsphere of this corner tetrahedron is centred at (1, 1.5, 2).
    let want_r = (1.0f64 + 2.25 + 4.0).sqrt();
    assert_rel(pore_body_radius_3d(&c, &[0.0; 4]), want_r, 1e-14);
    let cv = cell_volumes_3d(&c, &[0.0; 4]);
    assert_rel(cv.volume, 4.0, 1e-15);
    assert_eq!(cv.void_volume, cv.volume);
    // Circumcircle of the right triangle: half the hypotenuse.
    assert_rel(
        constriction_radius_3d(&[c[0], c[1], c[2]], &[0.0; 3]),
        13f64.sqrt() / 2.0,
        1e-14,
    );
    let t = throat_3d(
        [1.0, 1.0, 1.0],
        [1.0, 1.0, -1.0],
        &[c[0], c[1], c[2]],
        &[0.0; 3],
    );
    assert_rel(t.fluid_area, 3.0, 1e-15);
    assert_rel(t.void_volume, 2.0, 1e-15);
    assert_eq!(t.solid_surface, 0.0);
    assert_eq!(t.hydraulic_radius, 0.0);
}

#[test]
fn poiseuille_tube_check_of_formula() {
    for &(a, l, mu) in &[(1.0, 1.0, 1.0), (0.3, 7.0, 1e-3), (2e-4, 1e-2, 0.89)] {
        let g = conductance(PI * a * a, a / 2.0, l, mu);
        assert_rel(g, PI * a.powi(4) / (8.0 * mu * l), 1e-14);
    }
}

// ---- sign rule ----

/// Per-tetrahedron void and surface from the public cell function: a
/// zero-radius sphere at the power centre adds no sector.
fn tet_parts(p: V3, c: &[V3; 3], r: &[f64; 3]) -> (f64, f64) {
    let cv = cell_volumes_3d(&[p, c[0], c[1], c[2]], &[0.0, r[0], r[1], r[2]]);
    let mut surf = 0.0;
    for v in 0..3 {
        let (j, k) = ((v + 1) % 3, (v + 2) % 3);
        let om = solid_angle(sub3(p, c[v]), sub3(c[j], c[v]), sub3(c[k], c[v]));
        surf += r[v] * r[v] * om;
    }
    (cv.void_volume, surf)
}

#[test]
fn sign_rule_sum_and_difference() {
    let c = [[0.0, 0.0, 0.0], [1.0, 0.1, 0.0], [0.3, 0.9, 0.05]];
    let r = [0.2, 0.15, 0.25];
    let g = scale3(add3(add3(c[0], c[1]), c[2]), 1.0 / 3.0);
    let n = cross3(sub3(c[1], c[0]), sub3(c[2], c[0]));
    let up = add3(g, scale3(n, 0.6 / norm3(n)));
    let down = add3(g, add3(scale3(n, -0.4 / norm3(n)), [0.05, -0.02, 0.0]));
    let low = add3(g, scale3(n, 0.3 / norm3(n)));
    let (v_up, s_up) = tet_parts(up, &c, &r);
    let (v_down, s_down) = tet_parts(down, &c, &r);
    let (v_low, s_low) = tet_parts(low, &c, &r);

    let t = throat_3d(up, down, &c, &r);
    assert_rel(t.void_volume, v_up + v_down, 1e-12);
    assert_rel(t.solid_surface, s_up + s_down, 1e-12);
    assert_rel(t.hydraulic_radius, t.void_volume / t.solid_surface, 1e-15);
    let t2 = throat_3d(up, low, &c, &r);
    assert_rel(t2.void_volume, v_up - v_low, 1e-12);
    assert_rel(t2.solid_surface, s_up - s_low, 1e-12);
    for (a, b) in [(up, down), (down, up), (up, low), (low, up)] {
        let x = throat_3d(a, b, &c, &r);
        let y = throat_3d(b, a, &c, &r);
        assert_eq!(x, y);
        assert!(x.void_volume > 0.0 && x.solid_surface > 0.0);
    }
    assert_rel(t.length, dist3(up, down), 1e-15);
}

// ---- Monte Carlo ----

fn in_tet(x: V3, t: &[V3; 4]) -> bool {
    let vol = |a: V3, b: V3, c: V3, d: V3| dot3(sub3(b, a), cross3(sub3(c, a), sub3(d, a)));
    let s = vol(t[0], t[1], t[2], t[3]).signum();
    vol(x, t[1], t[2], t[3]) * s >= 0.0
        && vol(t[0], x, t[2], t[3]) * s >= 0.0
        && vol(t[0], t[1], x, t[3]) * s >= 0.0
        && vol(t[0], t[1], t[2], x) * s >= 0.0
}

fn in_tri(x: V2, t: &[V2; 3]) -> bool {
    let s = cross2(sub2(t[1], t[0]), sub2(t[2], t[0])).signum();
    (0..3).all(|i| cross2(sub2(t[(i + 1) % 3], t[i]), sub2(x, t[i])) * s >= 0.0)
}

fn tet_volume(t: &[V3; 4]) -> f64 {
    dot3(sub3(t[1], t[0]), cross3(sub3(t[2], t[0]), sub3(t[3], t[0]))).abs() / 6.0
}

fn tri_area(t: &[V2; 3]) -> f64 {
    cross2(sub2(t[1], t[0]), sub2(t[2], t[0])).abs() / 2.0
}

/// Uniform point in a simplex: normalised exponentials are Dirichlet(1,…,1).
fn bary<const N: usize>(rng: &mut StdRng) -> [f64; N] {
    let e = [0.0; N].map(|_: f64| -(1.0 - rng.random::<f64>()).ln());
    let s: f64 = e.iter().sum();
    e.map(|x| x / s)
}

fn sample_tet(rng: &mut StdRng, t: &[V3; 4]) -> V3 {
    let b = bary::<4>(rng);
    (0..4).fold([0.0; 3], |s, i| add3(s, scale3(t[i], b[i])))
}

fn sample_tri(rng: &mut StdRng, t: &[V2; 3]) -> V2 {
    let b = bary::<3>(rng);
    (0..3).fold([0.0; 2], |s, i| {
        [s[0] + b[i] * t[i][0], s[1] + b[i] * t[i][1]]
    })
}

/// Void volume of `t` minus `hole` (if any) by sampling `t` uniformly.
fn mc_void_3d(
    rng: &mut StdRng,
    t: &[V3; 4],
    hole: Option<&[V3; 4]>,
    balls: &[(V3, f64)],
    n: usize,
) -> f64 {
    let mut hits = 0usize;
    for _ in 0..n {
        let x = sample_tet(rng, t);
        let in_hole = hole.is_some_and(|h| in_tet(x, h));
        if !in_hole && balls.iter().all(|(c, r)| dist3(x, *c) > *r) {
            hits += 1;
        }
    }
    tet_volume(t) * hits as f64 / n as f64
}

/// Uniform point on the cap of `axis` (unit) with half-angle `alpha`.
fn sample_cap(rng: &mut StdRng, axis: V3, alpha: f64) -> V3 {
    let z = 1.0 - rng.random::<f64>() * (1.0 - alpha.cos());
    let phi = 2.0 * PI * rng.random::<f64>();
    let s = (1.0 - z * z).sqrt();
    let helper = if axis[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let u = cross3(axis, helper);
    let u = scale3(u, 1.0 / norm3(u));
    let v = cross3(axis, u);
    add3(
        scale3(axis, z),
        add3(scale3(u, s * phi.cos()), scale3(v, s * phi.sin())),
    )
}

/// Sphere surface and sphere volume inside `region`, by sampling each
/// sphere (and ball) only within the cap around the cone of `hull` at its
/// centre: `region ⊂ hull` and `hull` is convex, so nothing is missed, and
/// the samples are not wasted on the far side of the sphere.
fn mc_solid_3d(
    rng: &mut StdRng,
    hull: &[V3; 4],
    balls: &[(usize, f64)],
    region: impl Fn(V3) -> bool,
    n: usize,
) -> (f64, f64) {
    let (mut surface, mut volume) = (0.0, 0.0);
    for &(i, r) in balls {
        let c = hull[i];
        let dirs: Vec<V3> = (0..4)
            .filter(|&j| j != i)
            .map(|j| {
                let e = sub3(hull[j], c);
                scale3(e, 1.0 / norm3(e))
            })
            .collect();
        let sum = dirs.iter().fold([0.0; 3], |s, x| add3(s, *x));
        let axis = scale3(sum, 1.0 / norm3(sum));
        let alpha = dirs.iter().map(|e| angle3(axis, *e)).fold(0.0, f64::max);
        assert!(alpha < 0.5 * PI, "cap must be convex");
        let cap = 2.0 * PI * (1.0 - alpha.cos());
        let mut hits_s = 0usize;
        let mut hits_v = 0usize;
        for _ in 0..n {
            let u = sample_cap(rng, axis, alpha);
            hits_s += region(add3(c, scale3(u, r))) as usize;
            let rho = r * rng.random::<f64>().cbrt();
            hits_v += region(add3(c, scale3(u, rho))) as usize;
        }
        surface += cap * r * r * hits_s as f64 / n as f64;
        volume += cap * r.powi(3) / 3.0 * hits_v as f64 / n as f64;
    }
    (surface, volume)
}

/// Checks the sector assumption: each sphere stays on its side of the
/// face opposite its centre.
fn sectors_exact_3d(t: &[V3; 4], r: &[f64; 4]) -> bool {
    (0..4).all(|i| {
        let o: Vec<V3> = (0..4).filter(|&j| j != i).map(|j| t[j]).collect();
        r[i] <= plane_dist(t[i], o[0], o[1], o[2])
    })
}

const MC_N: usize = 600_000;

#[test]
fn cell_void_3d_monte_carlo() {
    let mut rng = StdRng::seed_from_u64(0x5eed_0001);
    let touching = (regular_tet(1.0, [0.0; 3]), [0.5; 4]);
    let mut cases = vec![touching];
    for _ in 0..3 {
        let pert: Vec<f64> = (0..12).map(|_| rng.random_range(-0.15..0.15)).collect();
        let f: Vec<f64> = (0..4).map(|_| rng.random_range(0.5..0.95)).collect();
        cases.push(tet_cell(&pert, &f, [1.0, 2.0, 3.0]));
    }
    for (c, r) in cases {
        assert!(sectors_exact_3d(&c, &r));
        let balls: Vec<(V3, f64)> = (0..4).map(|i| (c[i], r[i])).collect();
        let mc = mc_void_3d(&mut rng, &c, None, &balls, MC_N);
        let cv = cell_volumes_3d(&c, &r);
        assert!(!cv.clamped);
        assert_rel(cv.void_volume, mc, 0.01);
    }
}

#[test]
fn cell_void_2d_monte_carlo() {
    let mut rng = StdRng::seed_from_u64(0x5eed_0002);
    let mut cases = vec![(equilateral(1.0, [0.0; 2]), [0.5; 3])];
    for _ in 0..3 {
        let pert: Vec<f64> = (0..6).map(|_| rng.random_range(-0.15..0.15)).collect();
        let f: Vec<f64> = (0..3).map(|_| rng.random_range(0.5..0.95)).collect();
        cases.push(tri_cell(&pert, &f, [-2.0, 1.0]));
    }
    for (c, r) in cases {
        for i in 0..3 {
            assert!(r[i] <= line_dist(c[i], c[(i + 1) % 3], c[(i + 2) % 3]));
        }
        let hits = (0..MC_N)
            .filter(|_| {
                let x = sample_tri(&mut rng, &c);
                (0..3).all(|i| norm2(sub2(x, c[i])) > r[i])
            })
            .count();
        let mc = tri_area(&c) * hits as f64 / MC_N as f64;
        assert_rel(cell_volumes_2d(&c, &r).void_volume, mc, 0.01);
    }
}

/// A facet with two power centres: `up` above it, `down` below it, and
/// `low` above it on the segment from the facet centroid to `up`.
fn throat_case() -> ([V3; 3], [f64; 3], V3, V3, V3) {
    let c = [[0.0, 0.0, 0.0], [1.0, 0.1, 0.0], [0.35, 0.9, 0.05]];
    let r = [0.3, 0.25, 0.2];
    let g = scale3(add3(add3(c[0], c[1]), c[2]), 1.0 / 3.0);
    let n = cross3(sub3(c[1], c[0]), sub3(c[2], c[0]));
    let nu = scale3(n, 1.0 / norm3(n));
    let up = add3(g, add3(scale3(nu, 0.7), [0.05, -0.03, 0.0]));
    let down = add3(g, add3(scale3(nu, -0.5), [-0.04, 0.02, 0.01]));
    let low = add3(g, scale3(sub3(up, g), 0.75));
    (c, r, up, down, low)
}

fn tet_of(p: V3, c: &[V3; 3]) -> [V3; 4] {
    [p, c[0], c[1], c[2]]
}

#[test]
fn throat_3d_opposite_sides_monte_carlo() {
    let mut rng = StdRng::seed_from_u64(0x5eed_0003);
    let (c, r, up, down, _) = throat_case();
    let (t1, t2) = (tet_of(up, &c), tet_of(down, &c));
    let rr = [0.0, r[0], r[1], r[2]];
    assert!(sectors_exact_3d(&t1, &rr) && sectors_exact_3d(&t2, &rr));
    let balls: Vec<(V3, f64)> = (0..3).map(|i| (c[i], r[i])).collect();
    let void = mc_void_3d(&mut rng, &t1, None, &balls, MC_N)
        + mc_void_3d(&mut rng, &t2, None, &balls, MC_N);
    let idx: Vec<(usize, f64)> = (0..3).map(|i| (i + 1, r[i])).collect();
    let (mut surf, mut solid) = (0.0, 0.0);
    for t in [&t1, &t2] {
        let (s, v) = mc_solid_3d(&mut rng, t, &idx, |x| in_tet(x, t), MC_N);
        surf += s;
        solid += v;
    }
    let t = throat_3d(up, down, &c, &r);
    assert_rel(t.void_volume, void, 0.01);
    assert_rel(t.solid_surface, surf, 0.01);
    let region = tet_volume(&t1) + tet_volume(&t2);
    assert_rel(region - t.void_volume, solid, 0.01);
}

#[test]
fn throat_3d_same_side_monte_carlo() {
    let mut rng = StdRng::seed_from_u64(0x5eed_0004);
    let (c, r, up, _, low) = throat_case();
    let (t1, t2) = (tet_of(up, &c), tet_of(low, &c));
    let rr = [0.0, r[0], r[1], r[2]];
    assert!(sectors_exact_3d(&t1, &rr) && sectors_exact_3d(&t2, &rr));
    let balls: Vec<(V3, f64)> = (0..3).map(|i| (c[i], r[i])).collect();
    let void = mc_void_3d(&mut rng, &t1, Some(&t2), &balls, MC_N);
    let idx: Vec<(usize, f64)> = (0..3).map(|i| (i + 1, r[i])).collect();
    let in_region = |x| in_tet(x, &t1) && !in_tet(x, &t2);
    let (surf, solid) = mc_solid_3d(&mut rng, &t1, &idx, in_region, MC_N);
    let region = tet_volume(&t1) - tet_volume(&t2);
    for t in [throat_3d(up, low, &c, &r), throat_3d(low, up, &c, &r)] {
        assert_rel(t.void_volume, void, 0.01);
        assert_rel(t.solid_surface, surf, 0.01);
        assert_rel(region - t.void_volume, solid, 0.01);
    }
}

/// Cases with two externally tangent solutions (a small disc/sphere
/// between two big ones: one tangent circle on each side of it). Newton
/// from two starts finds both; the closed form must return the smaller.
#[test]
fn smallest_positive_root_is_chosen() {
    let c = [[-1.0, 0.0], [1.0, 0.0], [0.0, 0.5]];
    let r = [0.9, 0.9, 0.05];
    let newton2 = |y0: f64| {
        let z = newton([0.0, y0, 0.1], |z| {
            let mut fz = [0.0; 3];
            let mut j = [[0.0; 3]; 3];
            for i in 0..3 {
                let dv = sub2([z[0], z[1]], c[i]);
                let m = norm2(dv);
                fz[i] = m - r[i] - z[2];
                j[i] = [dv[0] / m, dv[1] / m, -1.0];
            }
            (fz, j)
        });
        z.unwrap()[2]
    };
    let (lo, hi) = (newton2(0.3), newton2(1.2));
    assert!(lo > 0.0 && hi > 1.5 * lo, "{lo} {hi}");
    assert_rel(pore_body_radius_2d(&c, &r), lo, 1e-12);

    let c3 = [
        [-1.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 0.5, 0.3],
        [0.0, 0.5, -0.3],
    ];
    let r3 = [0.9, 0.9, 0.05, 0.05];
    let newton3 = |y0: f64| {
        let z = newton([0.0, y0, 0.0, 0.1], |z| {
            let mut fz = [0.0; 4];
            let mut j = [[0.0; 4]; 4];
            for i in 0..4 {
                let dv = sub3([z[0], z[1], z[2]], c3[i]);
                let m = norm3(dv);
                fz[i] = m - r3[i] - z[3];
                j[i] = [dv[0] / m, dv[1] / m, dv[2] / m, -1.0];
            }
            (fz, j)
        });
        z.unwrap()[3]
    };
    let (lo, hi) = (newton3(0.3), newton3(1.2));
    assert!(lo > 0.0 && hi > 1.5 * lo, "{lo} {hi}");
    assert_rel(pore_body_radius_3d(&c3, &r3), lo, 1e-12);
    let f = [c3[0], c3[1], c3[2]];
    let fr = [r3[0], r3[1], r3[2]];
    let in_plane = newton_constriction_3d(&f, &fr).unwrap();
    assert_rel(constriction_radius_3d(&f, &fr), in_plane, 1e-9);
}

#[test]
fn throat_2d_monte_carlo() {
    let mut rng = StdRng::seed_from_u64(0x5eed_0005);
    let c = [[0.0, 0.0], [1.0, 0.2]];
    let r = [0.35, 0.3];
    let up = [0.45, 0.8];
    let down = [0.6, -0.5];
    let low = [0.48, 0.55];
    for (p1, p2, same_side) in [(up, down, false), (up, low, true)] {
        let t1 = [p1, c[0], c[1]];
        let t2 = [p2, c[0], c[1]];
        for t in [&t1, &t2] {
            assert!(r[0] <= line_dist(c[0], t[0], c[1]) && r[1] <= line_dist(c[1], t[0], c[0]));
        }
        let outside = |x: V2| (0..2).all(|i| norm2(sub2(x, c[i])) > r[i]);
        let mut void = 0.0;
        let region_parts = if same_side {
            vec![(t1, Some(t2))]
        } else {
            vec![(t1, None), (t2, None)]
        };
        for (t, hole) in region_parts {
            let hits = (0..MC_N)
                .filter(|_| {
                    let x = sample_tri(&mut rng, &t);
                    outside(x) && !hole.is_some_and(|h| in_tri(x, &h))
                })
                .count();
            void += tri_area(&t) * hits as f64 / MC_N as f64;
        }
        let in_region = |x: V2| {
            if same_side {
                in_tri(x, &t1) && !in_tri(x, &t2)
            } else {
                in_tri(x, &t1) || in_tri(x, &t2)
            }
        };
        let mut perim = 0.0;
        for i in 0..2 {
            let hits = (0..MC_N)
                .filter(|_| {
                    let a = 2.0 * PI * rng.random::<f64>();
                    in_region([c[i][0] + r[i] * a.cos(), c[i][1] + r[i] * a.sin()])
                })
                .count();
            perim += 2.0 * PI * r[i] * hits as f64 / MC_N as f64;
        }
        let t = throat_2d(p1, p2, &c, &r);
        assert_rel(t.void_volume, void, 0.01);
        assert_rel(t.solid_surface, perim, 0.01);
        assert_rel(t.fluid_area, norm2(sub2(c[1], c[0])) - 0.65, 1e-14);
        assert_eq!(t, throat_2d(p2, p1, &c, &r));
    }
}

// ---- degenerate inputs ----

fn all_finite_throat(t: &ThroatGeometry) -> bool {
    [
        t.length,
        t.fluid_area,
        t.void_volume,
        t.solid_surface,
        t.hydraulic_radius,
    ]
    .iter()
    .all(|x| x.is_finite())
}

fn check_all_finite_3d(c: &[V3; 4], r: &[f64; 4]) {
    if let Some((p, pw)) = power_centre_3d(c, r) {
        assert!(p.iter().all(|x| x.is_finite()) && pw.is_finite());
    }
    assert!(pore_body_radius_3d(c, r).is_finite());
    let cv = cell_volumes_3d(c, r);
    assert!(cv.volume.is_finite() && cv.void_volume.is_finite());
    let f = [c[0], c[1], c[2]];
    let fr = [r[0], r[1], r[2]];
    assert!(constriction_radius_3d(&f, &fr).is_finite());
    let t = throat_3d(c[3], c[0], &f, &fr);
    assert!(all_finite_throat(&t), "{t:?}");
    let t = throat_3d(c[3], [-c[3][0], c[3][1], -c[3][2]], &f, &fr);
    assert!(all_finite_throat(&t), "{t:?}");
    let g = conductance(t.fluid_area, t.hydraulic_radius, t.length, 1e-3);
    assert!(g.is_finite());
}

fn check_all_finite_2d(c: &[V2; 3], r: &[f64; 3]) {
    if let Some((p, pw)) = power_centre_2d(c, r) {
        assert!(p.iter().all(|x| x.is_finite()) && pw.is_finite());
    }
    assert!(pore_body_radius_2d(c, r).is_finite());
    let cv = cell_volumes_2d(c, r);
    assert!(cv.volume.is_finite() && cv.void_volume.is_finite());
    assert!(constriction_radius_2d(&[c[0], c[1]], &[r[0], r[1]]).is_finite());
    let t = throat_2d(c[2], [c[2][0], -c[2][1]], &[c[0], c[1]], &[r[0], r[1]]);
    assert!(all_finite_throat(&t), "{t:?}");
    let t = throat_2d(c[2], c[0], &[c[0], c[1]], &[r[0], r[1]]);
    assert!(all_finite_throat(&t), "{t:?}");
}

#[test]
fn coplanar_and_collinear_cells() {
    let c = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.4, 0.3, 0.0],
    ];
    let r = [0.2; 4];
    assert!(power_centre_3d(&c, &r).is_none());
    assert_eq!(pore_body_radius_3d(&c, &r), 0.0);
    let cv = cell_volumes_3d(&c, &r);
    assert_eq!(cv.volume, 0.0);
    assert_eq!(cv.void_volume, 0.0);
    assert!(cv.clamped);
    check_all_finite_3d(&c, &r);
    // Power centre in the facet plane: flat tetrahedron, no contribution.
    let f = [c[0], c[1], c[2]];
    let t = throat_3d(c[3], [0.3, 0.3, 0.5], &f, &[0.2; 3]);
    let (v, s) = tet_parts([0.3, 0.3, 0.5], &f, &[0.2; 3]);
    assert_rel(t.void_volume, v, 1e-13);
    assert_rel(t.solid_surface, s, 1e-13);

    let line = [[0.0, 0.0, 0.0], [1.0, 1.0, 1.0], [2.0, 2.0, 2.0]];
    assert_eq!(constriction_radius_3d(&line, &[0.1; 3]), 0.0);
    let t = throat_3d([0.0, 1.0, 0.0], [0.0, -1.0, 0.0], &line, &[0.1; 3]);
    assert_eq!(t.fluid_area, 0.0);
    assert_eq!(t.void_volume, 0.0);
    assert!(all_finite_throat(&t));

    let c2 = [[0.0, 0.0], [1.0, 1.0], [3.0, 3.0]];
    assert!(power_centre_2d(&c2, &[0.1; 3]).is_none());
    assert_eq!(pore_body_radius_2d(&c2, &[0.1; 3]), 0.0);
    check_all_finite_2d(&c2, &[0.1; 3]);
}

#[test]
fn coincident_and_non_finite_inputs() {
    let same = [[1.0, 2.0, 3.0]; 4];
    assert!(power_centre_3d(&same, &[1.0; 4]).is_none());
    check_all_finite_3d(&same, &[1.0; 4]);
    check_all_finite_2d(&[[1.0, 1.0]; 3], &[1.0; 3]);
    let bad = [f64::NAN, f64::INFINITY, -f64::INFINITY];
    for x in bad {
        let mut c = regular_tet(1.0, [0.0; 3]);
        c[1][2] = x;
        check_all_finite_3d(&c, &[0.3; 4]);
        check_all_finite_3d(&regular_tet(1.0, [0.0; 3]), &[0.3, x, 0.3, 0.3]);
        let mut t = equilateral(1.0, [0.0; 2]);
        t[2][0] = x;
        check_all_finite_2d(&t, &[0.3; 3]);
        check_all_finite_2d(&equilateral(1.0, [0.0; 2]), &[x, 0.3, 0.3]);
        assert!(throat_3d([x; 3], [0.0; 3], &[[1.0, 0.0, 0.0]; 3], &[0.1; 3]).void_volume == 0.0);
        assert!(conductance(x, 1.0, 1.0, 1.0).is_finite());
        assert!(conductance(1.0, 1.0, x, 1.0).is_finite());
    }
    assert_eq!(conductance(1.0, 1.0, 0.0, 1.0), 0.0);
    assert_eq!(conductance(1.0, 1.0, 1.0, 0.0), 0.0);
}

#[test]
fn touching_overlapping_and_zero_radii() {
    let c = regular_tet(1.0, [0.0; 3]);
    for r in [
        [0.0; 4],
        [0.5; 4],
        [0.6; 4],
        [0.0, 0.5, 0.5, 0.5],
        [2.0; 4],
        [1e-300; 4],
    ] {
        check_all_finite_3d(&c, &r);
    }
    // Overlap so strong that the spheres cover the whole cell: no pore.
    assert_eq!(pore_body_radius_3d(&c, &[0.7; 4]), 0.0);
    assert!(cell_volumes_3d(&c, &[2.0; 4]).clamped);
    let t = equilateral(1.0, [0.0; 2]);
    for r in [[0.0; 3], [0.5; 3], [0.6; 3], [2.0; 3]] {
        check_all_finite_2d(&t, &r);
    }
    assert_eq!(pore_body_radius_2d(&t, &[0.6; 3]), 0.0);
}

#[test]
fn huge_and_tiny_scales() {
    for s in [1e-300, 1e-200, 1e-150, 1e150, 1e200, 1e300] {
        let c = regular_tet(s, [0.0; 3]);
        check_all_finite_3d(&c, &[0.5 * s; 4]);
        let c = regular_tet(s, [s * 3.0, -s, 0.0]);
        check_all_finite_3d(&c, &[0.3 * s; 4]);
        check_all_finite_2d(&equilateral(s, [s, 0.0]), &[0.5 * s; 3]);
        // Radii stay exact where volumes would over/underflow.
        let want = 0.5 * s * (1.5f64.sqrt() - 1.0);
        assert_rel(
            pore_body_radius_3d(&regular_tet(s, [0.0; 3]), &[0.5 * s; 4]),
            want,
            1e-12,
        );
    }
    let v = cell_volumes_3d(&regular_tet(1e300, [0.0; 3]), &[0.0; 4]);
    assert_eq!(v.volume, f64::MAX);
}

// ---- overlapping spheres ----

/// A tetrahedron whose vertex spheres (radii `r`) overlap pairwise by
/// `delta` of the smaller radius: edges `r_i + r_j − δ min(r_i, r_j)`.
fn overlapping_tet(r: [f64; 4], delta: f64, origin: V3) -> [V3; 4] {
    let d = |i: usize, j: usize| r[i] + r[j] - delta * r[i].min(r[j]);
    let x2 = (d(0, 2).powi(2) - d(1, 2).powi(2) + d(0, 1).powi(2)) / (2.0 * d(0, 1));
    let y2 = (d(0, 2).powi(2) - x2 * x2).sqrt();
    let x3 = (d(0, 3).powi(2) - d(1, 3).powi(2) + d(0, 1).powi(2)) / (2.0 * d(0, 1));
    let y3 = (d(0, 3).powi(2) - d(2, 3).powi(2) + x2 * x2 + y2 * y2 - 2.0 * x2 * x3) / (2.0 * y2);
    let z3 = (d(0, 3).powi(2) - x3 * x3 - y3 * y3).sqrt();
    [[0.0; 3], [d(0, 1), 0.0, 0.0], [x2, y2, 0.0], [x3, y3, z3]].map(|p| add3(p, origin))
}

/// Solid angle at vertex `i` by Girard's theorem, Σ dihedral − π, the
/// dihedral angles from the faces' outward normals: a route apart from
/// the code's (Van Oosterom & Strackee).
fn girard_solid_angle(c: &[V3; 4], i: usize) -> f64 {
    let mut sum = 0.0;
    for j in (0..4).filter(|&j| j != i) {
        let km: Vec<usize> = (0..4).filter(|&x| x != i && x != j).collect();
        let (k, m) = (km[0], km[1]);
        let e = sub3(c[j], c[i]);
        let outward = |a: usize, away: usize| {
            let n = cross3(e, sub3(c[a], c[i]));
            if dot3(n, sub3(c[away], c[i])) > 0.0 {
                scale3(n, -1.0)
            } else {
                n
            }
        };
        let (n1, n2) = (outward(k, m), outward(m, k));
        sum += PI - (dot3(n1, n2) / (norm3(n1) * norm3(n2))).acos();
    }
    sum - PI
}

/// A unit vector perpendicular to `u` and a third completing the frame.
fn frame_of(u: V3) -> (V3, V3) {
    let helper = if u[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let v = cross3(u, helper);
    let v = scale3(v, 1.0 / norm3(v));
    (v, cross3(u, v))
}

/// Volume of `B_i ∩ B_j ∩ region` by uniform sampling of the cylinder
/// around their lens, and its standard error.
fn mc_lens_3d(
    rng: &mut StdRng,
    (ci, ri): (V3, f64),
    (cj, rj): (V3, f64),
    region: impl Fn(V3) -> bool,
    n: usize,
) -> (f64, f64) {
    let d = dist3(ci, cj);
    let u = scale3(sub3(cj, ci), 1.0 / d);
    let (v, w) = frame_of(u);
    let (lo, hi) = (d - rj, ri);
    let x = (d * d + ri * ri - rj * rj) / (2.0 * d);
    let rho = (ri * ri - x * x).sqrt();
    let mut hits = 0usize;
    for _ in 0..n {
        let t = lo + (hi - lo) * rng.random::<f64>();
        let rad = rho * rng.random::<f64>().sqrt();
        let a = 2.0 * PI * rng.random::<f64>();
        let p = add3(
            add3(ci, scale3(u, t)),
            add3(scale3(v, rad * a.cos()), scale3(w, rad * a.sin())),
        );
        if dist3(p, ci) <= ri && dist3(p, cj) <= rj && region(p) {
            hits += 1;
        }
    }
    let cyl = PI * rho * rho * (hi - lo);
    let p = hits as f64 / n as f64;
    (cyl * p, cyl * (p * (1.0 - p) / n as f64).sqrt())
}

/// Area of the cap of sphere `i` inside ball `j` that lies in `region`,
/// by uniform sampling of the cap, and its standard error.
fn mc_cap_3d(
    rng: &mut StdRng,
    (ci, ri): (V3, f64),
    (cj, rj): (V3, f64),
    region: impl Fn(V3) -> bool,
    n: usize,
) -> (f64, f64) {
    let d = dist3(ci, cj);
    let u = scale3(sub3(cj, ci), 1.0 / d);
    let cos_alpha = (d * d + ri * ri - rj * rj) / (2.0 * d * ri);
    let alpha = cos_alpha.acos();
    let hits = (0..n)
        .filter(|_| region(add3(ci, scale3(sample_cap(rng, u, alpha), ri))))
        .count();
    let cap = 2.0 * PI * ri * ri * (1.0 - cos_alpha);
    let p = hits as f64 / n as f64;
    (cap * p, cap * (p * (1.0 - p) / n as f64).sqrt())
}

/// Area of the lens of two discs inside `region` by a midpoint grid of
/// `n × n` over the lens' bounding box (error a few `1/n` of the lens).
fn grid_lens_2d(
    (ci, ri): (V2, f64),
    (cj, rj): (V2, f64),
    region: impl Fn(V2) -> bool,
    n: usize,
) -> f64 {
    let d = norm2(sub2(cj, ci));
    let u = [(cj[0] - ci[0]) / d, (cj[1] - ci[1]) / d];
    let v = [-u[1], u[0]];
    let (lo, hi) = (d - rj, ri);
    let x = (d * d + ri * ri - rj * rj) / (2.0 * d);
    let rho = (ri * ri - x * x).sqrt();
    let mut hits = 0usize;
    for a in 0..n {
        let t = lo + (hi - lo) * (a as f64 + 0.5) / n as f64;
        for b in 0..n {
            let s = rho * (2.0 * (b as f64 + 0.5) / n as f64 - 1.0);
            let p = [ci[0] + t * u[0] + s * v[0], ci[1] + t * u[1] + s * v[1]];
            if norm2(sub2(p, ci)) <= ri && norm2(sub2(p, cj)) <= rj && region(p) {
                hits += 1;
            }
        }
    }
    (hi - lo) * 2.0 * rho * hits as f64 / (n * n) as f64
}

/// The triangle's corner angles by the law of cosines.
fn cosine_law_angles(t: &[V2; 3]) -> [f64; 3] {
    std::array::from_fn(|i| {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        let (a, b, c) = (
            norm2(sub2(t[j], t[i])),
            norm2(sub2(t[k], t[i])),
            norm2(sub2(t[k], t[j])),
        );
        ((a * a + b * b - c * c) / (2.0 * a * b)).acos()
    })
}

const OVERLAPS: [f64; 3] = [0.001, 0.01, 0.05];
const RADII: [[f64; 4]; 2] = [[0.5; 4], [1.0, 0.8, 0.9, 0.7]];

/// The void of a cell whose four spheres all overlap (0.1 %, 1 %, 5 %
/// of the smaller radius; equal and unequal radii) against the cell less
/// the sectors (Girard's solid angles) plus each lens' part in the cell
/// sampled on its own: 4σ of that sampling, a few 1e-4 of a lens. The
/// sectors alone (the formula before overlaps) miss by over 30σ.
#[test]
fn overlapping_cell_void_3d_against_sampled_lenses() {
    let mut rng = StdRng::seed_from_u64(0x5eed_0101);
    for r in RADII {
        for delta in OVERLAPS {
            let c = overlapping_tet(r, delta, [0.3, -1.2, 2.0]);
            let cv = cell_volumes_3d(&c, &r);
            assert!(!cv.overlap_inexact && !cv.clamped, "{r:?} {delta}");
            let mut want = tet_volume(&c);
            for i in 0..4 {
                want -= r[i].powi(3) * girard_solid_angle(&c, i) / 3.0;
            }
            let (mut lenses, mut var) = (0.0, 0.0);
            for i in 0..4 {
                for j in i + 1..4 {
                    let (v, s) = mc_lens_3d(
                        &mut rng,
                        (c[i], r[i]),
                        (c[j], r[j]),
                        |x| in_tet(x, &c),
                        200_000,
                    );
                    lenses += v;
                    var += s * s;
                }
            }
            let sigma = var.sqrt();
            let got = cv.void_volume;
            assert!(
                (got - (want + lenses)).abs() <= 4.0 * sigma + 1e-12,
                "{r:?} δ {delta}: {got} vs {} ± {sigma}",
                want + lenses
            );
            assert!(lenses > 30.0 * sigma, "{lenses} ± {sigma}");
        }
    }
}

/// The same cells at 5 % overlap against a plain Monte Carlo of the
/// points of the cell outside every sphere, with no formula at all.
#[test]
fn overlapping_cell_void_3d_monte_carlo() {
    let mut rng = StdRng::seed_from_u64(0x5eed_0102);
    for r in RADII {
        let c = overlapping_tet(r, 0.05, [-1.0, 0.5, 0.25]);
        let balls: Vec<(V3, f64)> = (0..4).map(|i| (c[i], r[i])).collect();
        let n = 2_000_000;
        let mc = mc_void_3d(&mut rng, &c, None, &balls, n);
        let vol = tet_volume(&c);
        let p = mc / vol;
        let sigma = vol * (p * (1.0 - p) / n as f64).sqrt();
        let got = cell_volumes_3d(&c, &r).void_volume;
        assert!((got - mc).abs() <= 4.0 * sigma, "{got} vs {mc} ± {sigma}");
        let sectors_only: f64 = vol
            - (0..4)
                .map(|i| r[i].powi(3) * girard_solid_angle(&c, i) / 3.0)
                .sum::<f64>();
        assert!(
            (sectors_only - mc).abs() > 8.0 * sigma,
            "{sectors_only} vs {mc}"
        );
    }
}

/// A triangle of overlapping discs, and the facet of overlapping
/// spheres in its tilted plane (its fluid area), against the triangle
/// less the sectors (law-of-cosines angles) plus each lens' part in the
/// triangle on a fine grid.
#[test]
fn overlapping_triangle_and_facet_against_a_grid() {
    for r in RADII {
        for delta in OVERLAPS {
            let c3 = overlapping_tet(r, delta, [0.0; 3]);
            // The facet c0 c1 c2 lies in the plane z = 0.
            let t: [V2; 3] = std::array::from_fn(|i| [c3[i][0], c3[i][1]]);
            let rr = [r[0], r[1], r[2]];
            let theta = cosine_law_angles(&t);
            let mut want = tri_area(&t);
            let mut lenses = 0.0;
            for i in 0..3 {
                want -= 0.5 * rr[i] * rr[i] * theta[i];
                let j = (i + 1) % 3;
                lenses += grid_lens_2d((t[i], rr[i]), (t[j], rr[j]), |x| in_tri(x, &t), 1500);
            }
            let tol = 5e-3 * lenses + 1e-13;
            let cv = cell_volumes_2d(&t, &rr);
            assert!(!cv.overlap_inexact && !cv.clamped);
            assert!(
                (cv.void_volume - (want + lenses)).abs() <= tol,
                "2D {r:?} δ {delta}: {} vs {}",
                cv.void_volume,
                want + lenses
            );
            // The facet, tilted and moved, through the throat.
            let tilt = |p: V3| {
                let e1 = scale3([1.0, 2.0, -0.5], 1.0 / norm3([1.0, 2.0, -0.5]));
                let e2 = cross3(e1, [0.3, -0.2, 1.0]);
                let e2 = scale3(e2, 1.0 / norm3(e2));
                add3([1.0, 5.0, -2.0], add3(scale3(e1, p[0]), scale3(e2, p[1])))
            };
            let f = [tilt(c3[0]), tilt(c3[1]), tilt(c3[2])];
            let g = scale3(add3(add3(f[0], f[1]), f[2]), 1.0 / 3.0);
            let n = cross3(sub3(f[1], f[0]), sub3(f[2], f[0]));
            let nu = scale3(n, 1.0 / norm3(n));
            let th = throat_3d(add3(g, scale3(nu, 1.5)), add3(g, scale3(nu, -1.2)), &f, &rr);
            assert!(
                (th.fluid_area - (want + lenses)).abs() <= tol,
                "facet {r:?} δ {delta}: {} vs {}",
                th.fluid_area,
                want + lenses
            );
            // The sectors alone (the formula before overlaps) miss by
            // the lenses: far beyond the tolerance.
            assert!(lenses > 10.0 * tol, "{lenses} vs {tol}");
        }
    }
}

/// The throat region of a facet of overlapping spheres: its void (the
/// lenses' parts added back) and its solid surface (the caps inside the
/// other sphere taken off: not wetted), tetrahedron by tetrahedron
/// against Girard's sectors and the lenses and caps sampled on their own.
#[test]
fn overlapping_throat_region_against_sampled_lenses_and_caps() {
    let mut rng = StdRng::seed_from_u64(0x5eed_0103);
    for r in RADII {
        for delta in OVERLAPS {
            let c3 = overlapping_tet(r, delta, [0.2, 0.1, -0.3]);
            let f = [c3[0], c3[1], c3[2]];
            let rr = [r[0], r[1], r[2]];
            let g = scale3(add3(add3(f[0], f[1]), f[2]), 1.0 / 3.0);
            let n = cross3(sub3(f[1], f[0]), sub3(f[2], f[0]));
            let nu = scale3(n, 1.0 / norm3(n));
            let (up, down) = (
                add3(g, add3(scale3(nu, 1.5), [0.05, -0.03, 0.0])),
                add3(g, scale3(nu, -1.2)),
            );
            let th = throat_3d(up, down, &f, &rr);
            assert!(!th.overlap_inexact, "{r:?} {delta}");
            let (mut void, mut surf) = (0.0, 0.0);
            let (mut var_v, mut var_s) = (0.0, 0.0);
            let (mut lens_sum, mut cap_sum) = (0.0, 0.0);
            for p in [up, down] {
                let t = tet_of(p, &f);
                void += tet_volume(&t);
                for v in 0..3 {
                    let om = girard_solid_angle(&t, v + 1);
                    void -= rr[v].powi(3) * om / 3.0;
                    surf += rr[v] * rr[v] * om;
                }
                for (i, j) in [(0, 1), (1, 2), (0, 2)] {
                    let (a, b) = ((f[i], rr[i]), (f[j], rr[j]));
                    let (lv, ls) = mc_lens_3d(&mut rng, a, b, |x| in_tet(x, &t), 100_000);
                    let (ci, si) = mc_cap_3d(&mut rng, a, b, |x| in_tet(x, &t), 100_000);
                    let (cj, sj) = mc_cap_3d(&mut rng, b, a, |x| in_tet(x, &t), 100_000);
                    void += lv;
                    surf -= ci + cj;
                    lens_sum += lv;
                    cap_sum += ci + cj;
                    var_v += ls * ls;
                    var_s += si * si + sj * sj;
                }
            }
            let (sv, ss) = (var_v.sqrt(), var_s.sqrt());
            assert!(
                (th.void_volume - void).abs() <= 4.0 * sv + 1e-12,
                "{} vs {void} ± {sv}",
                th.void_volume
            );
            assert!(
                (th.solid_surface - surf).abs() <= 4.0 * ss + 1e-12,
                "{} vs {surf} ± {ss}",
                th.solid_surface
            );
            assert!(lens_sum > 30.0 * sv && cap_sum > 30.0 * ss);
            assert_rel(
                th.hydraulic_radius,
                th.void_volume / th.solid_surface,
                1e-15,
            );
        }
    }
}

/// Overlapping spheres leave the tangent sphere and circle of their gap
/// defined: both equal the independent Newton solution.
#[test]
fn overlapping_spheres_keep_their_pore_and_constriction_radii() {
    for r in RADII {
        for delta in OVERLAPS {
            let c = overlapping_tet(r, delta, [0.5, 0.5, 0.5]);
            let want = newton_tangent_3d(&c, &r).unwrap();
            assert!(want > 0.0);
            assert_rel(pore_body_radius_3d(&c, &r), want, 1e-9);
            let (f, fr) = ([c[1], c[2], c[3]], [r[1], r[2], r[3]]);
            let want = newton_constriction_3d(&f, &fr).unwrap();
            assert!(want > 0.0);
            assert_rel(constriction_radius_3d(&f, &fr), want, 1e-9);
            let t: [V2; 3] = std::array::from_fn(|i| [c[i][0], c[i][1]]);
            let want = newton_tangent_2d(&t, &[r[0], r[1], r[2]]).unwrap();
            assert_rel(pore_body_radius_2d(&t, &[r[0], r[1], r[2]]), want, 1e-9);
        }
    }
}

/// Three spheres sharing a point (20 % overlap of equal spheres): the
/// cell is flagged, its void is at least the true one (Bonferroni) and
/// at most the cell; their throat is closed.
#[test]
fn a_triple_overlap_is_flagged_bounded_and_closes_the_throat() {
    let mut rng = StdRng::seed_from_u64(0x5eed_0104);
    let c = regular_tet(1.0, [0.0; 3]);
    let r = [0.6; 4];
    let cv = cell_volumes_3d(&c, &r);
    assert!(cv.overlap_inexact);
    assert!(cv.void_volume <= cv.volume);
    let balls: Vec<(V3, f64)> = (0..4).map(|i| (c[i], r[i])).collect();
    let n = 1_000_000;
    let mc = mc_void_3d(&mut rng, &c, None, &balls, n);
    let vol = tet_volume(&c);
    let p = mc / vol;
    let sigma = vol * (p * (1.0 - p) / n as f64).sqrt();
    assert!(
        cv.void_volume >= mc - 4.0 * sigma,
        "{} vs {mc}",
        cv.void_volume
    );
    let f = [c[0], c[1], c[2]];
    assert_eq!(constriction_radius_3d(&f, &[0.6; 3]), 0.0);
    let t = throat_3d(c[3], scale3(c[3], -1.0), &f, &[0.6; 3]);
    assert!(t.overlap_inexact);
    assert!(all_finite_throat(&t));
    // Just short of sharing a point (circumradius 1/√3 = 0.5774): exact.
    let cv = cell_volumes_3d(&c, &[0.57; 4]);
    assert!(!cv.overlap_inexact);
    let t = equilateral(1.0, [0.0; 2]);
    assert!(cell_volumes_2d(&t, &[0.6; 3]).overlap_inexact);
    assert_eq!(pore_body_radius_2d(&t, &[0.6; 3]), 0.0);
    assert!(!cell_volumes_2d(&t, &[0.57; 3]).overlap_inexact);
}

/// The segment's series and its closed form agree where they meet, and
/// the 2D and 3D lenses match their textbook closed forms.
#[test]
fn lens_closed_forms() {
    // The closed form loses 1/α² of its digits here (~1e-13).
    let a = 0.05f64;
    assert_rel(segment(a * (1.0 - 1e-12)), a - a.sin() * a.cos(), 1e-11);
    // Two unit discs 1 apart: 2π/3 − √3/2; balls: π (2 − d)² (d + 4) / 12.
    let h = cap_heights(1.0, 1.0, 1.0).unwrap();
    assert_rel(
        lens_2d(1.0, 1.0, h).0,
        2.0 * PI / 3.0 - 0.75f64.sqrt(),
        1e-14,
    );
    assert_rel(lens_3d(1.0, 1.0, h).0, PI * 5.0 / 12.0, 1e-14);
    // Unequal: the classic formula with acos, fine at this overlap.
    let (ra, rb, d) = (1.0f64, 0.6f64, 1.3f64);
    let want = ra * ra * ((d * d + ra * ra - rb * rb) / (2.0 * d * ra)).acos()
        + rb * rb * ((d * d + rb * rb - ra * ra) / (2.0 * d * rb)).acos()
        - 0.5 * ((-d + ra + rb) * (d + ra - rb) * (d - ra + rb) * (d + ra + rb)).sqrt();
    assert_rel(
        lens_2d(ra, rb, cap_heights(ra, rb, d).unwrap()).0,
        want,
        1e-13,
    );
    let want3 =
        PI * (ra + rb - d).powi(2) * (d * d + 2.0 * d * (ra + rb) - 3.0 * (ra - rb).powi(2))
            / (12.0 * d);
    assert_rel(
        lens_3d(ra, rb, cap_heights(ra, rb, d).unwrap()).0,
        want3,
        1e-13,
    );
    assert!(cap_heights(1.0, 1.0, 2.0).is_none());
    assert!(cap_heights(0.0, 1.0, 0.5).is_none());
    // One inside the other: the small ball whole.
    assert_eq!(cap_heights(0.2, 1.0, 0.5), Some((0.4, 0.0)));
}

// ---- property tests ----

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn pore_radius_3d_matches_newton(
        pert in prop::collection::vec(-0.15f64..0.15, 12),
        f in prop::collection::vec(0.1f64..0.95, 4),
        ox in -10.0f64..10.0,
    ) {
        let (c, r) = tet_cell(&pert, &f, [ox, -ox, 0.5 * ox]);
        let num = newton_tangent_3d(&c, &r).expect("Newton failed");
        prop_assert!(num > 0.0);
        let got = pore_body_radius_3d(&c, &r);
        prop_assert!(rel_close(got, num, 1e-9), "{} vs {}", got, num);
    }

    #[test]
    fn pore_radius_2d_matches_newton(
        pert in prop::collection::vec(-0.15f64..0.15, 6),
        f in prop::collection::vec(0.1f64..0.95, 3),
        ox in -10.0f64..10.0,
    ) {
        let (c, r) = tri_cell(&pert, &f, [ox, 2.0 * ox]);
        let num = newton_tangent_2d(&c, &r).expect("Newton failed");
        prop_assert!(num > 0.0);
        let got = pore_body_radius_2d(&c, &r);
        prop_assert!(rel_close(got, num, 1e-9), "{} vs {}", got, num);
    }

    #[test]
    fn constriction_3d_matches_newton(
        pert in prop::collection::vec(-0.15f64..0.15, 12),
        f in prop::collection::vec(0.1f64..0.95, 4),
    ) {
        let (c, r) = tet_cell(&pert, &f, [0.3, 0.2, -0.1]);
        let (fc, fr) = ([c[1], c[2], c[3]], [r[1], r[2], r[3]]);
        let num = newton_constriction_3d(&fc, &fr).expect("Newton failed");
        prop_assert!(num > 0.0);
        let got = constriction_radius_3d(&fc, &fr);
        prop_assert!(rel_close(got, num, 1e-9), "{} vs {}", got, num);
    }

    #[test]
    fn power_centre_has_equal_powers(
        pert in prop::collection::vec(-0.15f64..0.15, 12),
        f in prop::collection::vec(0.0f64..0.95, 4),
    ) {
        let (c, r) = tet_cell(&pert, &f, [1.0, 1.0, 1.0]);
        let (p, pw) = power_centre_3d(&c, &r).unwrap();
        for i in 0..4 {
            let pi = dot3(sub3(p, c[i]), sub3(p, c[i])) - r[i] * r[i];
            prop_assert!((pi - pw).abs() < 1e-12);
        }
        let (t, tr) = tri_cell(&pert[..6], &f[..3], [2.0, 0.0]);
        let (p, pw) = power_centre_2d(&t, &tr).unwrap();
        for i in 0..3 {
            let d = sub2(p, t[i]);
            prop_assert!((dot2(d, d) - tr[i] * tr[i] - pw).abs() < 1e-12);
        }
    }

    /// Spherical excess: Ω at a vertex = Σ (dihedral angles at its three
    /// edges) − π, so Σ_i Ω_i = 2 Σ_edges φ_e − 4π; and Σ θ = π in 2D.
    #[test]
    fn solid_angle_sum_identity(
        pts in prop::collection::vec(-1.0f64..1.0, 12),
    ) {
        let c: [V3; 4] = std::array::from_fn(|i| [pts[3 * i], pts[3 * i + 1], pts[3 * i + 2]]);
        let vol = tet_volume(&c);
        let size = (0..4).flat_map(|i| (0..4).map(move |j| (i, j)))
            .map(|(i, j)| dist3(c[i], c[j])).fold(0.0, f64::max);
        prop_assume!(vol > 1e-3 * size.powi(3));
        let mut sum_omega = 0.0;
        for i in 0..4 {
            let e: Vec<V3> = (0..4).filter(|&j| j != i).map(|j| sub3(c[j], c[i])).collect();
            sum_omega += solid_angle(e[0], e[1], e[2]);
        }
        let mut sum_dihedral = 0.0;
        for i in 0..4 {
            for j in i + 1..4 {
                let kl: Vec<usize> = (0..4).filter(|&m| m != i && m != j).collect();
                let e = sub3(c[j], c[i]);
                let perp = |x: V3| {
                    let v = sub3(x, c[i]);
                    sub3(v, scale3(e, dot3(v, e) / dot3(e, e)))
                };
                sum_dihedral += angle3(perp(c[kl[0]]), perp(c[kl[1]]));
            }
        }
        prop_assert!((sum_omega - (2.0 * sum_dihedral - 4.0 * PI)).abs() < 1e-9);

        let t = [[pts[0], pts[1]], [pts[2], pts[3]], [pts[4], pts[5]]];
        prop_assume!(tri_area(&t) > 1e-6);
        let sum_theta: f64 = (0..3)
            .map(|i| angle2(sub2(t[(i + 1) % 3], t[i]), sub2(t[(i + 2) % 3], t[i])))
            .sum();
        prop_assert!((sum_theta - PI).abs() < 1e-12);
    }

    #[test]
    fn scaling_laws(
        pert in prop::collection::vec(-0.15f64..0.15, 12),
        f in prop::collection::vec(0.1f64..0.7, 4),
        log_s in -3.0f64..3.0,
        h in prop::collection::vec(0.3f64..1.0, 2),
    ) {
        let s = 10f64.powf(log_s);
        let (c, r) = tet_cell(&pert, &f, [0.2, -0.3, 0.1]);
        let cs = c.map(|x| scale3(x, s));
        let rs = r.map(|x| x * s);
        let close = |a: f64, b: f64, k: i32| rel_close(a * s.powi(k), b, 1e-12);
        prop_assert!(close(pore_body_radius_3d(&c, &r), pore_body_radius_3d(&cs, &rs), 1));
        let (v0, v1) = (cell_volumes_3d(&c, &r), cell_volumes_3d(&cs, &rs));
        prop_assert!(close(v0.volume, v1.volume, 3) && close(v0.void_volume, v1.void_volume, 3));
        let (f0, fr) = ([c[0], c[1], c[2]], [r[0], r[1], r[2]]);
        let (f1, fr1) = ([cs[0], cs[1], cs[2]], [rs[0], rs[1], rs[2]]);
        prop_assert!(close(constriction_radius_3d(&f0, &fr), constriction_radius_3d(&f1, &fr1), 1));
        let n = cross3(sub3(c[1], c[0]), sub3(c[2], c[0]));
        let g = scale3(add3(add3(c[0], c[1]), c[2]), 1.0 / 3.0);
        let p1 = add3(g, scale3(n, h[0] / norm3(n)));
        let p2 = add3(g, scale3(n, -h[1] / norm3(n)));
        let t0 = throat_3d(p1, p2, &f0, &fr);
        let t1 = throat_3d(scale3(p1, s), scale3(p2, s), &f1, &fr1);
        prop_assert!(close(t0.length, t1.length, 1));
        prop_assert!(close(t0.fluid_area, t1.fluid_area, 2));
        prop_assert!(close(t0.void_volume, t1.void_volume, 3));
        prop_assert!(close(t0.solid_surface, t1.solid_surface, 2));
        prop_assert!(close(t0.hydraulic_radius, t1.hydraulic_radius, 1));
        let mu = 1e-3;
        let g0 = conductance(t0.fluid_area, t0.hydraulic_radius, t0.length, mu);
        let g1 = conductance(t1.fluid_area, t1.hydraulic_radius, t1.length, mu);
        prop_assert!(g0 > 0.0 && close(g0, g1, 3));

        // 2D: radii ~ s, areas ~ s², conductance per unit depth ~ s².
        let (tc, tr) = tri_cell(&pert[..6], &f[..3], [0.1, 0.4]);
        let tcs = tc.map(|x| [x[0] * s, x[1] * s]);
        let trs = tr.map(|x| x * s);
        prop_assert!(close(pore_body_radius_2d(&tc, &tr), pore_body_radius_2d(&tcs, &trs), 1));
        let (a0, a1) = (cell_volumes_2d(&tc, &tr), cell_volumes_2d(&tcs, &trs));
        prop_assert!(close(a0.volume, a1.volume, 2) && close(a0.void_volume, a1.void_volume, 2));
        let e0 = [tc[0], tc[1]];
        let e1 = [tcs[0], tcs[1]];
        let q1 = tc[2];
        let q2 = [tc[0][0] + tc[1][0] - tc[2][0], tc[0][1] + tc[1][1] - tc[2][1]];
        let u0 = throat_2d(q1, q2, &e0, &[tr[0], tr[1]]);
        let u1 = throat_2d([q1[0] * s, q1[1] * s], [q2[0] * s, q2[1] * s], &e1, &[trs[0], trs[1]]);
        prop_assert!(close(u0.void_volume, u1.void_volume, 2));
        prop_assert!(close(u0.solid_surface, u1.solid_surface, 1));
        prop_assert!(close(u0.hydraulic_radius, u1.hydraulic_radius, 1));
        let g0 = conductance(u0.fluid_area, u0.hydraulic_radius, u0.length, mu);
        let g1 = conductance(u1.fluid_area, u1.hydraulic_radius, u1.length, mu);
        prop_assert!(close(g0, g1, 2));
    }
}
