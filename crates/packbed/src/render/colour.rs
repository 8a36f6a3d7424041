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
}
