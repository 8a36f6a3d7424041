//! Colour maps that survive printing and colour-blindness: the Okabe–Ito
//! categorical palette for species and classes, viridis for ordered values.

use super::canvas::Rgb;

/// Okabe & Ito (2008) colour-blind-safe palette, without its black and yellow
/// (black hides outlines; yellow vanishes on white paper).
pub const CATEGORICAL: [Rgb; 6] = [
    Rgb(0, 114, 178),   // blue
    Rgb(230, 159, 0),   // orange
    Rgb(0, 158, 115),   // bluish green
    Rgb(204, 121, 167), // reddish purple
    Rgb(86, 180, 233),  // sky blue
    Rgb(213, 94, 0),    // vermillion
];

/// The colour of category `k` (wraps around after six).
pub fn categorical(k: usize) -> Rgb {
    CATEGORICAL[k % CATEGORICAL.len()]
}

/// Colour of highlighted particles (percolation chains): vermillion.
pub const HIGHLIGHT: Rgb = Rgb(213, 94, 0);
/// Colour of the particles that are not highlighted: light grey.
pub const BACKGROUND_PARTICLE: Rgb = Rgb(205, 205, 205);

/// Viridis anchors at t = 0, 1/8, …, 1 (matplotlib's values).
const VIRIDIS: [Rgb; 9] = [
    Rgb(68, 1, 84),
    Rgb(71, 44, 122),
    Rgb(59, 81, 139),
    Rgb(44, 113, 142),
    Rgb(33, 144, 141),
    Rgb(39, 173, 129),
    Rgb(92, 200, 99),
    Rgb(170, 220, 50),
    Rgb(253, 231, 37),
];

/// Viridis at `t` in `[0, 1]` (clamped; NaN gives the low end).
pub fn viridis(t: f64) -> Rgb {
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    let x = t * (VIRIDIS.len() - 1) as f64;
    let i = (x.floor() as usize).min(VIRIDIS.len() - 2);
    VIRIDIS[i].mix(VIRIDIS[i + 1], x - i as f64)
}

/// Light to dark orange-red (ColorBrewer OrRd): tensile bond forces.
const TENSION: [Rgb; 3] = [Rgb(253, 212, 158), Rgb(239, 101, 72), Rgb(127, 0, 0)];
/// Light to dark blue (ColorBrewer Blues): compressive bond forces.
const COMPRESSION: [Rgb; 3] = [Rgb(198, 219, 239), Rgb(66, 146, 198), Rgb(8, 48, 107)];

fn ramp(stops: &[Rgb; 3], t: f64) -> Rgb {
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    if t < 0.5 {
        stops[0].mix(stops[1], 2.0 * t)
    } else {
        stops[1].mix(stops[2], 2.0 * t - 1.0)
    }
}

/// A tensile force of relative size `t` in `[0, 1]`: light orange to dark red
/// (clamped; NaN gives the light end).
pub fn tension(t: f64) -> Rgb {
    ramp(&TENSION, t)
}

/// A compressive force of relative size `t` in `[0, 1]`: light to dark blue
/// (clamped; NaN gives the light end).
pub fn compression(t: f64) -> Rgb {
    ramp(&COMPRESSION, t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn viridis_ends_and_clamping() {
        assert_eq!(viridis(0.0), VIRIDIS[0]);
        assert_eq!(viridis(1.0), VIRIDIS[8]);
        assert_eq!(viridis(-3.0), VIRIDIS[0]);
        assert_eq!(viridis(7.0), VIRIDIS[8]);
        assert_eq!(viridis(f64::NAN), VIRIDIS[0]);
        assert_eq!(viridis(0.5), VIRIDIS[4]);
    }

    #[test]
    fn categories_are_distinct() {
        for a in 0..6 {
            for b in 0..a {
                assert_ne!(categorical(a), categorical(b));
            }
        }
        assert_eq!(categorical(6), categorical(0));
    }

    #[test]
    fn force_ramps_darken_and_differ() {
        assert_eq!(tension(0.0), TENSION[0]);
        assert_eq!(tension(1.0), TENSION[2]);
        assert_eq!(compression(f64::NAN), COMPRESSION[0]);
        assert_eq!(compression(9.0), COMPRESSION[2]);
        let sum = |c: Rgb| c.0 as u32 + c.1 as u32 + c.2 as u32;
        for k in 0..10 {
            let (a, b) = (k as f64 / 10.0, (k + 1) as f64 / 10.0);
            assert!(sum(tension(b)) < sum(tension(a)));
            assert!(sum(compression(b)) < sum(compression(a)));
            // Red stays redder than blue along both ramps.
            assert!(tension(a).0 > compression(a).0 && tension(a).2 < compression(a).2);
        }
    }
}
