//! The standard normal distribution: its CDF, its inverse, and draws from it
//! truncated to a window, by inversion so that no window, however far in a
//! tail, makes a draw loop.

use super::Real;

/// `Φ(x)`, the standard normal CDF.
pub fn cdf(x: Real) -> Real {
    0.5 * libm::erfc(-x / std::f64::consts::SQRT_2)
}

/// `1 − Φ(x)`, exact in the upper tail where `Φ` itself rounds to 1.
pub fn upper(x: Real) -> Real {
    0.5 * libm::erfc(x / std::f64::consts::SQRT_2)
}

/// `Φ(x) − ½`: antisymmetric to the last bit, so that a window symmetric about 0
/// has its median at exactly 0.
fn centred(x: Real) -> Real {
    0.5 * libm::erf(x / std::f64::consts::SQRT_2)
}

/// `Φ⁻¹(p)`: Acklam's rational approximation (relative error 1.2e-9), polished by
/// one Halley step on `Φ` to full precision. `±∞` outside `(0, 1)`.
pub fn quantile(p: Real) -> Real {
    if p.is_nan() {
        return Real::NAN;
    }
    if p <= 0.0 {
        return Real::NEG_INFINITY;
    }
    if p >= 1.0 {
        return Real::INFINITY;
    }
    const A: [Real; 6] = [
        -3.969_683_028_665_376e1,
        2.209_460_984_245_205e2,
        -2.759_285_104_469_687e2,
        1.383_577_518_672_69e2,
        -3.066_479_806_614_716e1,
        2.506_628_277_459_239,
    ];
    const B: [Real; 5] = [
        -5.447_609_879_822_406e1,
        1.615_858_368_580_409e2,
        -1.556_989_798_598_866e2,
        6.680_131_188_771_972e1,
        -1.328_068_155_288_572e1,
    ];
    const C: [Real; 6] = [
        -7.784_894_002_430_293e-3,
        -3.223_964_580_411_365e-1,
        -2.400_758_277_161_838,
        -2.549_732_539_343_734,
        4.374_664_141_464_968,
        2.938_163_982_698_783,
    ];
    const D: [Real; 4] = [
        7.784_695_709_041_462e-3,
        3.224_671_290_700_398e-1,
        2.445_134_137_142_996,
        3.754_408_661_907_416,
    ];
    const P_LOW: Real = 0.02425;
    let tail = |q: Real| {
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    };
    let x = if p < P_LOW {
        tail((-2.0 * p.ln()).sqrt())
    } else if p <= 1.0 - P_LOW {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    } else {
        -tail((-2.0 * (1.0 - p).ln()).sqrt())
    };
    // Halley's step; the error of the upper tail is taken from `upper` so that
    // it keeps its digits where `Φ(x)` is within an ulp of 1.
    let e = if x > 0.0 {
        (1.0 - p) - upper(x)
    } else {
        cdf(x) - p
    };
    let u = e * (2.0 * std::f64::consts::PI).sqrt() * (0.5 * x * x).exp();
    let polished = x - u / (1.0 + 0.5 * x * u);
    if polished.is_finite() {
        polished
    } else {
        x
    }
}

/// The probability that a standard normal variate lies in `[a, b]` (`a <= b`).
pub fn mass(a: Real, b: Real) -> Real {
    if a >= 0.0 {
        upper(a) - upper(b)
    } else if b <= 0.0 {
        upper(-b) - upper(-a)
    } else {
        centred(b) - centred(a)
    }
}

/// The `u`-quantile (`u` in `[0, 1]`) of the standard normal truncated to
/// `[a, b]` (`a <= b`, holding some probability), always within `[a, b]`.
pub fn truncated_quantile(a: Real, b: Real, u: Real) -> Real {
    let z = if a >= 0.0 {
        // In the upper tail: interpolate the tail probabilities, which stay
        // exact where Φ(a) and Φ(b) would both round to 1.
        let (qa, qb) = (upper(a), upper(b));
        if qa == 0.0 {
            // Beyond 38 sd no probability is representable; the density falls
            // so steeply there that all of it sits at the near end.
            return a;
        }
        -quantile(qa - u * (qa - qb))
    } else if b <= 0.0 {
        let (pa, pb) = (upper(-a), upper(-b));
        if pb == 0.0 {
            return b;
        }
        quantile(pa + u * (pb - pa))
    } else {
        let (ca, cb) = (centred(a), centred(b));
        quantile(0.5 + (ca + u * (cb - ca)))
    };
    if z.is_nan() {
        return a;
    }
    z.clamp(a, b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cdf_at_known_points() {
        // Reference values computed to 30 digits (mpmath, `erfc`).
        for (x, p) in [
            (0.0, 0.5),
            (1.0, 0.841_344_746_068_542_9),
            (-1.0, 0.158_655_253_931_457_05),
            (2.0, 0.977_249_868_051_820_8),
            (-3.0, 0.001_349_898_031_630_094_6),
        ] {
            assert!((cdf(x) - p).abs() < 1e-15, "Φ({x}) = {} not {p}", cdf(x));
        }
        // 1 − Φ(10) = 7.6199e-24: the tail keeps its digits.
        assert!((upper(10.0) / 7.619_853_024_160_527e-24 - 1.0).abs() < 1e-12);
    }

    #[test]
    fn quantile_inverts_the_cdf() {
        let density = |x: Real| (-0.5 * x * x).exp() / (2.0 * std::f64::consts::PI).sqrt();
        let mut x = -37.0;
        while x <= 8.0 {
            let back = quantile(cdf(x));
            // Above 0, Φ(x) itself is only known to an ulp of 1, which moves
            // its inverse by ulp / density.
            let tol = 1e-12 * x.abs().max(1.0) + if x > 0.0 { 2.3e-16 / density(x) } else { 0.0 };
            assert!((back - x).abs() <= tol, "Φ⁻¹(Φ({x})) = {back}");
            x += 0.0625;
        }
        assert_eq!(quantile(0.5), 0.0);
        assert_eq!(quantile(0.0), Real::NEG_INFINITY);
        assert_eq!(quantile(1.0), Real::INFINITY);
    }

    #[test]
    fn truncated_quantiles_stay_in_the_window() {
        for (a, b) in [
            (-3.0, 3.0),
            (-1.0, 0.5),
            (4.0, 4.5),
            (30.0, 31.0),
            (-31.0, -30.0),
            (40.0, 50.0),
            (-50.0, -40.0),
            (5.0, Real::INFINITY),
            (2.0, 2.0),
            (-50.0, 50.0),
            (0.0, 1e-300),
        ] {
            for k in 0..=100 {
                let u = k as Real / 100.0;
                let z = truncated_quantile(a, b, u);
                assert!((a..=b).contains(&z), "[{a}, {b}] at {u}: {z}");
            }
            if mass(a, b) > 0.0 {
                let low = truncated_quantile(a, b, 0.0);
                assert!(
                    (low - a).abs() <= 1e-12 * a.abs().max(1.0),
                    "[{a}, {b}]: {low}"
                );
            }
        }
        assert_eq!(truncated_quantile(-3.0, 3.0, 0.5), 0.0);
        // Far in the tail the window's mass is mostly near its lower end: the
        // median of z > 30 is about 30 + ln 2 / 30.
        let m = truncated_quantile(30.0, 40.0, 0.5);
        assert!((m - (30.0 + 2.0f64.ln() / 30.0)).abs() < 1e-3, "{m}");
    }

    #[test]
    fn mass_of_windows() {
        assert!((mass(-3.0, 3.0) - 0.997_300_203_936_739_8).abs() < 1e-15);
        assert!((mass(-1.0, 1.0) - 0.682_689_492_137_085_9).abs() < 1e-15);
        assert_eq!(mass(10.0, Real::INFINITY), upper(10.0));
        // 1 − Φ(10) − (1 − Φ(11)), with both tails to 30 digits (mpmath).
        assert!(
            (mass(10.0, 11.0) / (7.619_853_024_160_527e-24 - 1.910_659_574_498_676e-28) - 1.0)
                .abs()
                < 1e-12
        );
        assert!((mass(-11.0, -10.0) / mass(10.0, 11.0) - 1.0).abs() < 1e-15);
        assert_eq!(mass(1.0, 1.0), 0.0);
    }
}
