use super::*;
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, Zero};
use proptest::prelude::*;

// ---------------------------------------------------------------- exact rational oracle

/// (mantissa, exponent) with x = m · 2^e exactly.
fn decode(x: f64) -> (i128, i64) {
    assert!(x.is_finite());
    let bits = x.to_bits();
    let exp = ((bits >> 52) & 0x7ff) as i64;
    let frac = (bits & ((1u64 << 52) - 1)) as i128;
    let (m, e) = if exp == 0 {
        (frac, -1074)
    } else {
        (frac | (1i128 << 52), exp - 1075)
    };
    if bits >> 63 == 1 {
        (-m, e)
    } else {
        (m, e)
    }
}

fn rat(x: f64) -> BigRational {
    let (m, e) = decode(x);
    let n = BigInt::from(m);
    if e >= 0 {
        BigRational::from_integer(n << (e as usize))
    } else {
        BigRational::new(n, BigInt::one() << ((-e) as usize))
    }
}

fn rsign(x: &BigRational) -> Sign {
    if x.is_positive() {
        1
    } else if x.is_negative() {
        -1
    } else {
        0
    }
}

fn rv(x: &[f64]) -> Vec<BigRational> {
    x.iter().map(|&v| rat(v)).collect()
}

fn oracle_orient2d(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> Sign {
    let (a, b, c) = (rv(&a), rv(&b), rv(&c));
    let u = [&b[0] - &a[0], &b[1] - &a[1]];
    let v = [&c[0] - &a[0], &c[1] - &a[1]];
    rsign(&(&u[0] * &v[1] - &u[1] * &v[0]))
}

fn oracle_orient3d(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) -> Sign {
    let (a, b, c, d) = (rv(&a), rv(&b), rv(&c), rv(&d));
    let sub = |x: &[BigRational], y: &[BigRational]| -> Vec<BigRational> {
        x.iter().zip(y).map(|(p, q)| p - q).collect()
    };
    let (u, v, w) = (sub(&b, &a), sub(&c, &a), sub(&d, &a));
    let cx = &v[1] * &w[2] - &v[2] * &w[1];
    let cy = &v[2] * &w[0] - &v[0] * &w[2];
    let cz = &v[0] * &w[1] - &v[1] * &w[0];
    rsign(&(&u[0] * cx + &u[1] * cy + &u[2] * cz))
}

/// Gaussian elimination over the rationals; None if singular.
#[allow(clippy::needless_range_loop)]
fn solve(mut a: Vec<Vec<BigRational>>, mut b: Vec<BigRational>) -> Option<Vec<BigRational>> {
    let n = b.len();
    for col in 0..n {
        let piv = (col..n).find(|&r| !a[r][col].is_zero())?;
        a.swap(col, piv);
        b.swap(col, piv);
        for r in col + 1..n {
            if a[r][col].is_zero() {
                continue;
            }
            let f = &a[r][col] / &a[col][col];
            for c in col..n {
                let t = &f * &a[col][c];
                a[r][c] -= t;
            }
            let t = &f * &b[col];
            b[r] -= t;
        }
    }
    let mut x = vec![BigRational::zero(); n];
    for r in (0..n).rev() {
        let mut s = b[r].clone();
        for c in r + 1..n {
            s -= &a[r][c] * &x[c];
        }
        x[r] = s / &a[r][r];
    }
    Some(x)
}

fn norm2(x: &[BigRational]) -> BigRational {
    x.iter().fold(BigRational::zero(), |s, v| s + v * v)
}

/// Independent oracle: solve for the orthosphere (c, k = |c|² - R) from
/// 2 c·p_i - k = |p_i|² - w_i, then the power distance of q is |q|² - 2 c·q + k - wq.
/// Returns +1 if it is negative; 0 if p is degenerate.
fn oracle_power(p: &[Vec<f64>], w: &[BigRational], q: &[f64], wq: &BigRational) -> Sign {
    let d = q.len();
    let two = BigRational::from_integer(BigInt::from(2));
    let mut a = Vec::new();
    let mut b = Vec::new();
    for (pi, wi) in p.iter().zip(w) {
        let pr = rv(pi);
        let mut row: Vec<BigRational> = pr.iter().map(|x| x * &two).collect();
        row.push(-BigRational::one());
        a.push(row);
        b.push(norm2(&pr) - wi);
    }
    let Some(sol) = solve(a, b) else { return 0 };
    let qr = rv(q);
    let mut pw = norm2(&qr) + &sol[d] - wq;
    for i in 0..d {
        pw -= &two * &sol[i] * &qr[i];
    }
    -rsign(&pw)
}

fn oracle_power_3d(p: [[f64; 3]; 4], w: [f64; 4], q: [f64; 3], wq: f64) -> Sign {
    let pv: Vec<Vec<f64>> = p.iter().map(|x| x.to_vec()).collect();
    oracle_power(&pv, &rv(&w), &q, &rat(wq))
}

fn oracle_power_2d(p: [[f64; 2]; 3], w: [f64; 3], q: [f64; 2], wq: f64) -> Sign {
    let pv: Vec<Vec<f64>> = p.iter().map(|x| x.to_vec()).collect();
    oracle_power(&pv, &rv(&w), &q, &rat(wq))
}

/// A K such that concrete perturbations eps_i = 2^(-K (n - pos_i)) are "infinitesimal"
/// for these inputs: coordinates are multiples of 2^g and < 2^(t+1), weights multiples of
/// 2^(2g) and < 2^(2t+2); D is a multiple of 2^(5g) and every minor is < 2^(3t+8).
fn concrete_k(coords: &[f64], weights: &[f64]) -> usize {
    let mut g = i64::MAX;
    let mut t = i64::MIN;
    let lohi = |x: f64| {
        let (m, e) = decode(x);
        let m = m.unsigned_abs();
        (
            e + m.trailing_zeros() as i64,
            e + 127 - m.leading_zeros() as i64,
        )
    };
    for &c in coords.iter().filter(|c| **c != 0.0) {
        let (lo, hi) = lohi(c);
        g = g.min(lo);
        t = t.max(hi);
    }
    for &c in weights.iter().filter(|c| **c != 0.0) {
        let (lo, hi) = lohi(c);
        g = g.min(lo.div_euclid(2));
        t = t.max((hi + 1).div_euclid(2));
    }
    if g == i64::MAX {
        return 64;
    }
    (6 * (-g).max(0) + 4 * t.max(0) + 64) as usize
}

/// Power test with the weights concretely perturbed in exact rationals.
fn oracle_perturbed(p: &[Vec<f64>], w: &[f64], ranks: &[u64], q: &[f64], wq: f64, rq: u64) -> Sign {
    let n = p.len() + 1;
    let mut all_ranks = ranks.to_vec();
    all_ranks.push(rq);
    let mut coords: Vec<f64> = p.iter().flatten().copied().collect();
    coords.extend_from_slice(q);
    let mut weights = w.to_vec();
    weights.push(wq);
    let k = concrete_k(&coords, &weights);
    let eps: Vec<BigRational> = (0..n)
        .map(|i| {
            let pos = all_ranks.iter().filter(|&&r| r < all_ranks[i]).count();
            BigRational::new(BigInt::one(), BigInt::one() << (k * (n - pos)))
        })
        .collect();
    let wr: Vec<BigRational> = (0..n - 1).map(|i| rat(w[i]) + &eps[i]).collect();
    let wqr = rat(wq) + &eps[n - 1];
    oracle_power(p, &wr, q, &wqr)
}

// ---------------------------------------------------------------- hand cases

const CUBE_EVEN: [[f64; 3]; 4] = [
    [1.0, 1.0, 1.0],
    [1.0, -1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
];

#[test]
fn hand_orient() {
    assert_eq!(orient2d([0.0, 0.0], [1.0, 0.0], [0.0, 1.0]), 1);
    assert_eq!(orient2d([0.0, 0.0], [0.0, 1.0], [1.0, 0.0]), -1);
    assert_eq!(orient2d([0.0, 0.0], [1.0, 1.0], [3.0, 3.0]), 0);
    assert_eq!(
        orient2d([0.1, 0.1], [0.2, 0.2], [0.3, 0.3]),
        oracle_orient2d([0.1, 0.1], [0.2, 0.2], [0.3, 0.3])
    );
    let o = [0.0; 3];
    let (e1, e2, e3) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]);
    assert_eq!(orient3d(o, e1, e2, e3), 1);
    assert_eq!(orient3d(o, e2, e1, e3), -1);
    assert_eq!(orient3d(o, e1, e2, [5.0, -7.0, 0.0]), 0);
    assert_eq!(orient3d(o, e1, e2, [5.0, -7.0, -1e-70]), -1);
    let c = CUBE_EVEN;
    assert_eq!(
        orient3d(c[0], c[1], c[2], c[3]),
        oracle_orient3d(c[0], c[1], c[2], c[3])
    );
    assert_ne!(orient3d(c[0], c[1], c[2], c[3]), 0);
}

#[test]
fn hand_power_3d() {
    let c = CUBE_EVEN;
    let w = [0.0; 4];
    let flipped = [c[1], c[0], c[2], c[3]];
    for p in [c, flipped] {
        assert_eq!(power_test_3d(p, w, [0.0; 3], 0.0), 1);
        assert_eq!(power_test_3d(p, w, [10.0, 0.0, 0.0], 0.0), -1);
        // Another corner of the cube is on the circumsphere.
        assert_eq!(power_test_3d(p, w, [-1.0, -1.0, -1.0], 0.0), 0);
        assert_eq!(power_test_3d(p, w, [-1.0, -1.0, -1.0], 0.5), 1);
        assert_eq!(power_test_3d(p, w, [-1.0, -1.0, -1.0], -0.5), -1);
        // Far point with a huge weight conflicts; centre with a large negative weight not.
        assert_eq!(power_test_3d(p, w, [10.0, 0.0, 0.0], 200.0), 1);
        assert_eq!(power_test_3d(p, w, [0.0; 3], -4.0), -1);
        assert_eq!(power_test_3d(p, w, [0.0; 3], -3.0), 0);
        // Uniform weights shift: same orthosphere centre, R = 3 - 1 → corner with weight 1 on it.
        assert_eq!(power_test_3d(p, [1.0; 4], [-1.0, -1.0, -1.0], 1.0), 0);
        // Perturbed: q on the sphere, highest rank → conflict.
        assert_eq!(
            power_test_3d_perturbed(p, w, [1, 2, 3, 4], [-1.0, -1.0, -1.0], 0.0, 9),
            1
        );
        // q lowest rank: decided by p[3] (rank 4), compare with the oracle.
        let got = power_test_3d_perturbed(p, w, [1, 2, 3, 4], [-1.0, -1.0, -1.0], 0.0, 0);
        let pv: Vec<Vec<f64>> = p.iter().map(|x| x.to_vec()).collect();
        let want = oracle_perturbed(&pv, &w, &[1, 2, 3, 4], &[-1.0, -1.0, -1.0], 0.0, 0);
        assert_eq!(got, want);
    }
    // Degenerate p.
    let flat = [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]];
    assert_eq!(power_test_3d(flat, [0.0; 4], [0.3, 0.3, 0.3], 0.0), 0);
    assert_eq!(
        power_test_3d_perturbed(flat, [0.0; 4], [0, 1, 2, 3], [0.3, 0.3, 0.3], 0.0, 4),
        0
    );
}

#[test]
fn hand_power_2d() {
    let p = [[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0]];
    let flipped = [p[1], p[0], p[2]];
    for p in [p, flipped] {
        let w = [0.0; 3];
        assert_eq!(power_test_2d(p, w, [0.0, 0.0], 0.0), 1);
        assert_eq!(power_test_2d(p, w, [0.0, -1.0], 0.0), 0);
        assert_eq!(power_test_2d(p, w, [0.0, -1.1], 0.0), -1);
        assert_eq!(power_test_2d(p, w, [0.0, -1.0], 1e-80), 1);
        assert_eq!(power_test_2d(p, [0.25; 3], [0.0, -1.0], 0.25), 0);
        assert_eq!(
            power_test_2d_perturbed(p, w, [0, 1, 2], [0.0, -1.0], 0.0, 3),
            1
        );
        for rq in 0..4u64 {
            let ranks: Vec<u64> = (0..4u64).filter(|&r| r != rq).collect();
            let ranks = [ranks[0], ranks[1], ranks[2]];
            let got = power_test_2d_perturbed(p, w, ranks, [0.0, -1.0], 0.0, rq);
            let pv: Vec<Vec<f64>> = p.iter().map(|x| x.to_vec()).collect();
            assert_eq!(
                got,
                oracle_perturbed(&pv, &w, &ranks, &[0.0, -1.0], 0.0, rq)
            );
        }
    }
}

/// The exact path alone must agree with the oracle (also where the filter would succeed).
#[test]
fn exact_path_agrees() {
    let mut rng = Lcg(7);
    for _ in 0..2000 {
        let mut p = [[0.0; 3]; 4];
        for x in p.iter_mut().flatten() {
            *x = rng.f64() * 2.0 - 1.0;
        }
        let w = [rng.f64(), rng.f64(), rng.f64(), rng.f64()];
        let q = [rng.f64(), rng.f64(), rng.f64()];
        let wq = rng.f64();
        let d = exp_sign(&power_det_3d_exact(&p, &w, q, wq));
        if let Some(t) = translated_det_sign_3d(&p, &w, q, wq) {
            assert_eq!(t, d);
        }
        let o = exp_sign(&orient3d_exact(p[0], p[1], p[2], p[3]));
        assert_eq!(o, oracle_orient3d(p[0], p[1], p[2], p[3]));
        assert_eq!(-d * o, oracle_power_3d(p, w, q, wq));
        let p2 = [[p[0][0], p[0][1]], [p[1][0], p[1][1]], [p[2][0], p[2][1]]];
        let d2 = exp_sign(&power_det_2d_exact(
            &p2,
            &[w[0], w[1], w[2]],
            [q[0], q[1]],
            wq,
        ));
        if let Some(t) = translated_det_sign_2d(&p2, &[w[0], w[1], w[2]], [q[0], q[1]], wq) {
            assert_eq!(t, d2);
        }
        let o2 = exp_sign(&orient2d_exact(p2[0], p2[1], p2[2]));
        assert_eq!(o2, oracle_orient2d(p2[0], p2[1], p2[2]));
        assert_eq!(
            d2 * o2,
            oracle_power_2d(p2, [w[0], w[1], w[2]], [q[0], q[1]], wq)
        );
    }
}

#[test]
fn expansion_arithmetic() {
    // (1 + 2^-60) · (1 - 2^-60) - 1 = -2^-120, invisible in plain f64.
    let a = exp_sum(&[2f64.powi(-60)], &[1.0]);
    let b = exp_sum(&[-(2f64.powi(-60))], &[1.0]);
    let p = exp_mul(&a, &b);
    let r = exp_compress(&exp_sum(&p, &[-1.0]));
    assert_eq!(r, vec![-(2f64.powi(-120))]);
    assert_eq!(exp_sign(&exp_sum(&[1e-300], &[-1e300, 1e300])), 1);
    assert_eq!(exp_sign(&[]), 0);
}

// ---------------------------------------------------------------- generators

struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        self.0 >> 11
    }
    fn f64(&mut self) -> f64 {
        self.next() as f64 / (1u64 << 53) as f64
    }
    fn int(&mut self, lo: i64, hi: i64) -> i64 {
        lo + (self.next() % ((hi - lo + 1) as u64)) as i64
    }
}

/// Five weighted points in 3D: p = pts[0..4], q = pts[4].
#[derive(Clone, Debug)]
struct Cfg3 {
    pts: [[f64; 3]; 5],
    w: [f64; 5],
}

/// Four weighted points in 2D: p = pts[0..3], q = pts[3].
#[derive(Clone, Debug)]
struct Cfg2 {
    pts: [[f64; 2]; 4],
    w: [f64; 4],
}

fn fi(v: i32) -> f64 {
    f64::from(v)
}

fn sphere_points(r2: i32) -> Vec<[f64; 3]> {
    let mut v = Vec::new();
    for x in -7..=7 {
        for y in -7..=7 {
            for z in -7..=7 {
                if x * x + y * y + z * z == r2 {
                    v.push([fi(x), fi(y), fi(z)]);
                }
            }
        }
    }
    v
}

fn scale_offset() -> impl Strategy<Value = (f64, f64)> {
    (
        prop::sample::select(vec![1.0, 0.5, 3.0, 1e-3, 0.1, 1e3, 2f64.powi(-40)]),
        prop::sample::select(vec![0.0, 1e6, 0.1, -7.25, 1e6 + 0.1, 123.456]),
    )
}

/// Degenerate or near-degenerate families (these are what stress the exact path).
fn arb_degenerate3() -> BoxedStrategy<Cfg3> {
    let lattice = (
        prop::array::uniform5(prop::array::uniform3(-2i32..=2)),
        prop::array::uniform5(0i32..=2),
    )
        .prop_map(|(p, w)| Cfg3 {
            pts: p.map(|x| x.map(fi)),
            w: w.map(fi),
        });
    // All five points orthogonal to the sphere (c/2, R): D = 0 exactly.
    let ortho = (
        prop::array::uniform5(prop::array::uniform3(-3i32..=3)),
        prop::array::uniform3(-3i32..=3),
        -4i32..=4,
    )
        .prop_map(|(p, c, r)| {
            let pts = p.map(|x| x.map(fi));
            let c = c.map(|v| fi(v) * 0.5);
            let w = pts.map(|x| {
                (x[0] - c[0]).powi(2) + (x[1] - c[1]).powi(2) + (x[2] - c[2]).powi(2) - fi(r)
            });
            Cfg3 { pts, w }
        });
    let sp = sphere_points(25);
    let n = sp.len();
    let sphere = (
        prop::array::uniform5(0..n),
        prop::sample::select(vec![0.0, 1.0, 2.5]),
        prop::array::uniform3(-2i32..=2),
    )
        .prop_map(move |(idx, w0, off)| Cfg3 {
            pts: idx.map(|i| [0, 1, 2].map(|k| sp[i][k] + fi(off[k]) * 0.5)),
            w: [w0; 5],
        });
    let cube = (
        prop::array::uniform5(0usize..8),
        scale_offset(),
        prop::sample::select(vec![0.0, 1.0, 0.3]),
    )
        .prop_map(|(idx, (s, t), w0)| Cfg3 {
            pts: idx.map(|i| [0, 1, 2].map(|k| t + s * if (i >> k) & 1 == 1 { 1.0 } else { -1.0 })),
            w: [w0; 5],
        });
    prop_oneof![lattice, ortho, sphere, cube].boxed()
}

fn arb_near3() -> BoxedStrategy<Cfg3> {
    let near = (
        prop::array::uniform5(prop::array::uniform3((-3i32..=3, -3i32..=3))),
        prop::array::uniform5((0i32..=3, -3i32..=3)),
    )
        .prop_map(|(p, w)| Cfg3 {
            pts: p.map(|x| x.map(|(i, k)| 0.1 * fi(i) + fi(k) * 1e-16)),
            w: w.map(|(i, k)| 0.01 * fi(i) + fi(k) * 1e-17),
        });
    let offset = (
        prop::array::uniform5(prop::array::uniform3((-2i32..=2, -2i32..=2))),
        prop::array::uniform5(0i32..=2),
    )
        .prop_map(|(p, w)| Cfg3 {
            pts: p.map(|x| x.map(|(i, k)| 1e6 + 0.5 * fi(i) + fi(k) * 1e-10)),
            w: w.map(|i| 0.25 * fi(i)),
        });
    let random = (
        prop::array::uniform5(prop::array::uniform3(-10.0f64..10.0)),
        prop::array::uniform5(0.0f64..5.0),
    )
        .prop_map(|(pts, w)| Cfg3 { pts, w });
    let tiny_huge = (
        prop::array::uniform5(prop::array::uniform3(-2i32..=2)),
        prop::array::uniform5(0i32..=2),
        prop::sample::select(vec![2f64.powi(-100), 2f64.powi(90), 1e-30, 1e30]),
    )
        .prop_map(|(p, w, s)| Cfg3 {
            pts: p.map(|x| x.map(|v| fi(v) * s)),
            w: w.map(|v| fi(v) * s * s),
        });
    // Points rounded from a sphere: nearly cospherical.
    let rounded = (
        prop::array::uniform5((0.0f64..std::f64::consts::PI, 0.0f64..6.3)),
        prop::sample::select(vec![0.0, 1.0, 1e6]),
    )
        .prop_map(|(ang, t)| Cfg3 {
            pts: ang.map(|(a, b)| [t + a.sin() * b.cos(), t + a.sin() * b.sin(), t + a.cos()]),
            w: [0.0; 5],
        });
    prop_oneof![near, offset, random, tiny_huge, rounded].boxed()
}

fn arb_cfg3() -> BoxedStrategy<Cfg3> {
    prop_oneof![arb_degenerate3(), arb_near3()].boxed()
}

fn to2(c: &Cfg3) -> Cfg2 {
    Cfg2 {
        pts: [0, 1, 2, 3].map(|i| [c.pts[i][0], c.pts[i][1]]),
        w: [c.w[0], c.w[1], c.w[2], c.w[3]],
    }
}

fn arb_degenerate2() -> BoxedStrategy<Cfg2> {
    // Circle x² + y² = 25 and 65 integer points; ortho family; lattice; cube → square.
    let circ: Vec<[f64; 2]> = (-8i32..=8)
        .flat_map(|x| (-8i32..=8).map(move |y| (x, y)))
        .filter(|(x, y)| x * x + y * y == 25 || x * x + y * y == 65)
        .map(|(x, y)| [fi(x), fi(y)])
        .collect();
    let n = circ.len();
    let circle = (
        prop::array::uniform4(0..n),
        prop::array::uniform2(-2i32..=2),
    )
        .prop_map(move |(idx, off)| {
            let pts = idx.map(|i| [circ[i][0] + fi(off[0]) * 0.5, circ[i][1] + fi(off[1])]);
            let c = [fi(off[0]) * 0.5, fi(off[1])];
            let w = pts.map(|x| {
                let r = (x[0] - c[0]).powi(2) + (x[1] - c[1]).powi(2);
                if r == 25.0 {
                    0.0
                } else {
                    40.0
                }
            });
            Cfg2 { pts, w }
        });
    prop_oneof![arb_degenerate3().prop_map(|c| to2(&c)), circle].boxed()
}

fn arb_cfg2() -> BoxedStrategy<Cfg2> {
    prop_oneof![arb_degenerate2(), arb_near3().prop_map(|c| to2(&c))].boxed()
}

fn distinct_ranks<const N: usize>() -> impl Strategy<Value = [u64; N]> {
    prop::collection::vec(any::<u64>(), N).prop_map(|v| {
        let mut r = [0u64; N];
        for (i, x) in v.iter().enumerate() {
            r[i] = (x >> 8 << 8) | i as u64;
        }
        r
    })
}

fn permutations(n: usize) -> Vec<Vec<usize>> {
    if n == 0 {
        return vec![vec![]];
    }
    let mut out = Vec::new();
    for p in permutations(n - 1) {
        for pos in 0..=p.len() {
            let mut q = p.clone();
            q.insert(pos, n - 1);
            out.push(q);
        }
    }
    out
}

fn check3(c: &Cfg3, ranks: &[u64; 5], with_perturbed: bool) -> Result<(), TestCaseError> {
    let p = [c.pts[0], c.pts[1], c.pts[2], c.pts[3]];
    let w = [c.w[0], c.w[1], c.w[2], c.w[3]];
    let (q, wq) = (c.pts[4], c.w[4]);
    let o = orient3d(p[0], p[1], p[2], p[3]);
    prop_assert_eq!(o, oracle_orient3d(p[0], p[1], p[2], p[3]));
    prop_assert_eq!(
        orient3d(p[1], p[2], p[3], q),
        oracle_orient3d(p[1], p[2], p[3], q)
    );
    let want = oracle_power_3d(p, w, q, wq);
    prop_assert_eq!(power_test_3d(p, w, q, wq), want);
    let rp = [ranks[0], ranks[1], ranks[2], ranks[3]];
    let pert = power_test_3d_perturbed(p, w, rp, q, wq, ranks[4]);
    if with_perturbed {
        let pv: Vec<Vec<f64>> = p.iter().map(|x| x.to_vec()).collect();
        let want_p = oracle_perturbed(&pv, &w, &rp, &q, wq, ranks[4]);
        prop_assert_eq!(pert, want_p);
    }
    prop_assert!(want == 0 || pert == want);
    prop_assert_eq!(pert == 0, o == 0);
    if o != 0 {
        // The later stages on their own, wherever they apply: sign(D) = −want · o.
        let det_sign = -want * o;
        if let Some(d) = exact_differences(&p, q) {
            if let Some(s) = dw_det_sign_3d(&d, &w, wq) {
                prop_assert_eq!(s, det_sign);
            }
        }
        if let Some(s) = translated_det_sign_3d(&p, &w, q, wq) {
            prop_assert_eq!(s, det_sign);
        }
    }
    for perm in permutations(4) {
        let pp = [0, 1, 2, 3].map(|i| p[perm[i]]);
        let ww = [0, 1, 2, 3].map(|i| w[perm[i]]);
        let rr = [0, 1, 2, 3].map(|i| rp[perm[i]]);
        prop_assert_eq!(power_test_3d(pp, ww, q, wq), want);
        prop_assert_eq!(power_test_3d_perturbed(pp, ww, rr, q, wq, ranks[4]), pert);
    }
    Ok(())
}

fn check2(c: &Cfg2, ranks: &[u64; 4], with_perturbed: bool) -> Result<(), TestCaseError> {
    let p = [c.pts[0], c.pts[1], c.pts[2]];
    let w = [c.w[0], c.w[1], c.w[2]];
    let (q, wq) = (c.pts[3], c.w[3]);
    let o = orient2d(p[0], p[1], p[2]);
    prop_assert_eq!(o, oracle_orient2d(p[0], p[1], p[2]));
    prop_assert_eq!(orient2d(p[1], p[2], q), oracle_orient2d(p[1], p[2], q));
    let want = oracle_power_2d(p, w, q, wq);
    prop_assert_eq!(power_test_2d(p, w, q, wq), want);
    let rp = [ranks[0], ranks[1], ranks[2]];
    let pert = power_test_2d_perturbed(p, w, rp, q, wq, ranks[3]);
    if with_perturbed {
        let pv: Vec<Vec<f64>> = p.iter().map(|x| x.to_vec()).collect();
        let want_p = oracle_perturbed(&pv, &w, &rp, &q, wq, ranks[3]);
        prop_assert_eq!(pert, want_p);
    }
    prop_assert!(want == 0 || pert == want);
    prop_assert_eq!(pert == 0, o == 0);
    if o != 0 {
        // The later stages on their own: sign(D) = want · o.
        let det_sign = want * o;
        if let Some(d) = exact_differences(&p, q) {
            if let Some(s) = dw_det_sign_2d(&d, &w, wq) {
                prop_assert_eq!(s, det_sign);
            }
        }
        if let Some(s) = translated_det_sign_2d(&p, &w, q, wq) {
            prop_assert_eq!(s, det_sign);
        }
    }
    for perm in permutations(3) {
        let pp = [0, 1, 2].map(|i| p[perm[i]]);
        let ww = [0, 1, 2].map(|i| w[perm[i]]);
        let rr = [0, 1, 2].map(|i| rp[perm[i]]);
        prop_assert_eq!(power_test_2d(pp, ww, q, wq), want);
        prop_assert_eq!(power_test_2d_perturbed(pp, ww, rr, q, wq, ranks[3]), pert);
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]

    #[test]
    fn prop_power3_vs_oracle(c in arb_cfg3(), r in distinct_ranks::<5>()) {
        check3(&c, &r, false)?;
    }

    #[test]
    fn prop_power2_vs_oracle(c in arb_cfg2(), r in distinct_ranks::<4>()) {
        check2(&c, &r, false)?;
    }

    #[test]
    fn prop_power3_perturbed_vs_oracle(c in arb_degenerate3(), r in distinct_ranks::<5>()) {
        check3(&c, &r, true)?;
    }

    #[test]
    fn prop_power2_perturbed_vs_oracle(c in arb_degenerate2(), r in distinct_ranks::<4>()) {
        check2(&c, &r, true)?;
    }

    #[test]
    fn prop_orient_vs_oracle(
        pts in prop::array::uniform4(prop::array::uniform3(prop_oneof![
            (-3i32..=3).prop_map(fi),
            -1e3f64..1e3,
            (-3i32..=3, -3i32..=3).prop_map(|(i, k)| 0.1 * fi(i) + fi(k) * 1e-16),
            (-3i32..=3).prop_map(|k| 1e6 + fi(k) * 2f64.powi(-30)),
            (-3i32..=3).prop_map(|k| fi(k) * 1e-70),
        ]))
    ) {
        let [a, b, c, d] = pts;
        prop_assert_eq!(orient3d(a, b, c, d), oracle_orient3d(a, b, c, d));
        let (a2, b2, c2) = ([a[0], a[1]], [b[0], b[1]], [c[0], c[1]]);
        prop_assert_eq!(orient2d(a2, b2, c2), oracle_orient2d(a2, b2, c2));
        // Collinear / coplanar by construction: midpoints on lattice lines.
        let m2 = [(a2[0] + b2[0]) * 0.5, (a2[1] + b2[1]) * 0.5];
        prop_assert_eq!(orient2d(a2, b2, m2), oracle_orient2d(a2, b2, m2));
    }
}

/// Deterministic sweep over orthogonal (D = 0) configurations, counting that the
/// perturbation is really exercised and resolved by different points.
#[test]
fn perturbed_sweep_counts() {
    let mut rng = Lcg(99);
    let mut decided_by_q = 0;
    let mut degenerate = 0;
    for _ in 0..3000 {
        let mut pts = [[0.0; 3]; 5];
        for x in pts.iter_mut().flatten() {
            *x = rng.int(-2, 2) as f64;
        }
        let c = [rng.int(-2, 2) as f64 * 0.5, rng.int(-2, 2) as f64, 0.5];
        let r = rng.int(-3, 3) as f64;
        let w =
            pts.map(|x| (x[0] - c[0]).powi(2) + (x[1] - c[1]).powi(2) + (x[2] - c[2]).powi(2) - r);
        let p = [pts[0], pts[1], pts[2], pts[3]];
        if orient3d(p[0], p[1], p[2], p[3]) == 0 {
            continue;
        }
        let wp = [w[0], w[1], w[2], w[3]];
        assert_eq!(power_test_3d(p, wp, pts[4], w[4]), 0);
        degenerate += 1;
        let mut ranks = [0u64, 1, 2, 3, 4];
        for i in (1..5).rev() {
            ranks.swap(i, rng.int(0, i as i64) as usize);
        }
        let rp = [ranks[0], ranks[1], ranks[2], ranks[3]];
        let got = power_test_3d_perturbed(p, wp, rp, pts[4], w[4], ranks[4]);
        let pv: Vec<Vec<f64>> = p.iter().map(|x| x.to_vec()).collect();
        assert_eq!(
            got,
            oracle_perturbed(&pv, &wp, &rp, &pts[4], w[4], ranks[4])
        );
        if ranks[4] == 4 {
            decided_by_q += 1;
            assert_eq!(got, 1);
        }
    }
    assert!(degenerate > 1000, "{degenerate}");
    assert!(decided_by_q > 100, "{decided_by_q}");
}

/// Rough timing (run with `cargo test --release -- --ignored --nocapture`).
#[test]
#[ignore]
fn bench_filtered() {
    use std::hint::black_box;
    use std::time::Instant;
    let mut rng = Lcg(1);
    let n = 1 << 14;
    type Case = ([[f64; 3]; 4], [f64; 4], [f64; 3], f64);
    let cases: Vec<Case> = (0..n)
        .map(|_| {
            let mut p = [[0.0; 3]; 4];
            for x in p.iter_mut().flatten() {
                *x = rng.f64();
            }
            let w = [0; 4].map(|_| 0.01 * rng.f64());
            let q = [rng.f64(), rng.f64(), rng.f64()];
            (p, w, q, 0.01 * rng.f64())
        })
        .collect();
    let reps = 200;
    let mut acc = 0i64;
    let t = Instant::now();
    for _ in 0..reps {
        for c in &cases {
            acc += power_test_3d(
                black_box(c.0),
                black_box(c.1),
                black_box(c.2),
                black_box(c.3),
            ) as i64;
        }
    }
    let ns = t.elapsed().as_nanos() as f64 / (reps * n) as f64;
    println!("power_test_3d: {ns:.1} ns/call (acc {acc})");
    let t = Instant::now();
    for _ in 0..reps {
        for c in &cases {
            acc += orient3d(
                black_box(c.0[0]),
                black_box(c.0[1]),
                black_box(c.0[2]),
                black_box(c.2),
            ) as i64;
        }
    }
    let ns = t.elapsed().as_nanos() as f64 / (reps * n) as f64;
    println!("orient3d: {ns:.1} ns/call (acc {acc})");
    let t = Instant::now();
    for _ in 0..reps {
        for c in &cases {
            acc += power_test_3d_perturbed(
                black_box(c.0),
                black_box(c.1),
                [0, 1, 2, 3],
                black_box(c.2),
                black_box(c.3),
                4,
            ) as i64;
        }
    }
    let ns = t.elapsed().as_nanos() as f64 / (reps * n) as f64;
    println!("power_test_3d_perturbed: {ns:.1} ns/call (acc {acc})");
    // Exact-path cost on degenerate input (cospherical cube corners).
    let reps = 20000;
    let t = Instant::now();
    for _ in 0..reps {
        acc += power_test_3d(
            black_box(CUBE_EVEN),
            [0.0; 4],
            black_box([-1.0, -1.0, -1.0]),
            0.0,
        ) as i64;
    }
    let ns = t.elapsed().as_nanos() as f64 / reps as f64;
    println!("power_test_3d (exact fallback, degenerate): {ns:.1} ns/call (acc {acc})");
}

/// The oriented variants equal the perturbed tests wherever `p` is
/// positively oriented, on lattice points full of ties.
#[test]
fn oriented_variants_agree_with_the_perturbed_tests() {
    let mut seed = 12345u64;
    let mut next = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((seed >> 33) % 3) as f64
    };
    let (mut checked3, mut checked2) = (0, 0);
    for k in 0..20000u64 {
        let p: [[f64; 3]; 4] = [
            [next(), next(), next()],
            [next(), next(), next()],
            [next(), next(), next()],
            [next(), next(), next()],
        ];
        let q = [next(), next(), next()];
        let w = [next() * 0.5, next() * 0.5, next() * 0.5, next() * 0.5];
        let wq = next() * 0.5;
        let rank = [k * 5, k * 5 + 3, k * 5 + 1, k * 5 + 4];
        if orient3d(p[0], p[1], p[2], p[3]) > 0 {
            checked3 += 1;
            let want = power_test_3d_perturbed(p, w, rank, q, wq, k * 5 + 2);
            assert_eq!(power_test_3d_oriented(p, w, rank, q, wq, k * 5 + 2), want);
            assert_eq!(
                power_test_3d_oriented_lazy(p, w, q, wq, || (rank, k * 5 + 2)),
                want
            );
        }
        let p2 = [[p[0][0], p[0][1]], [p[1][0], p[1][1]], [p[2][0], p[2][1]]];
        if orient2d(p2[0], p2[1], p2[2]) > 0 {
            checked2 += 1;
            let r = [rank[0], rank[1], rank[2]];
            let w2 = [w[0], w[1], w[2]];
            let want = power_test_2d_perturbed(p2, w2, r, [q[0], q[1]], wq, k * 5 + 2);
            assert_eq!(
                power_test_2d_oriented(p2, w2, r, [q[0], q[1]], wq, k * 5 + 2),
                want
            );
            assert_eq!(
                power_test_2d_oriented_lazy(p2, w2, [q[0], q[1]], wq, || (r, k * 5 + 2)),
                want
            );
        }
    }
    assert!(checked3 > 1000 && checked2 > 1000, "{checked3} {checked2}");
}
