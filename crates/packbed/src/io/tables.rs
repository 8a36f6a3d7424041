//! The CSV files of a run: `particles.csv`, `contacts.csv`, `wall_contacts.csv`.
//!
//! Numbers are written as the shortest text that reads back to the same bits
//! (Rust's `Display`/`LowerExp` for `f64`), so the files round-trip exactly. The
//! columns are numeric (wall names aside) and never quoted, so a plain writer is
//! enough.

use crate::analysis::Contacts;
use crate::bed::Bed;
use std::fmt;
use std::io::{Error, Write};

/// An `f64` in the shortest exact form: plain decimals for ordinary magnitudes,
/// exponent notation for tiny or huge ones (a contact gap of 3.6e-15 would
/// otherwise take 30 characters of zeros).
#[derive(Clone, Copy, Debug)]
pub struct Num(pub f64);

impl fmt::Display for Num {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let a = self.0.abs();
        if a == 0.0 || (1e-5..1e16).contains(&a) {
            write!(f, "{}", self.0)
        } else {
            write!(f, "{:e}", self.0)
        }
    }
}

impl Num {
    /// Appends the text [`Display`](fmt::Display) writes, about three times
    /// faster: the shortest digits that read back to the same bits come from
    /// `ryu` (the same digits as the standard library's, which also picks
    /// the shortest and then the nearest: a property test compares the two),
    /// laid out as the standard library lays them out. The pore network's
    /// files are some 5 GB of such numbers at 10^6 spheres.
    pub(crate) fn push_to(self, out: &mut Vec<u8>) {
        let v = self.0;
        if !v.is_finite() {
            // The tables refuse these before; the exports write them as before.
            out.extend_from_slice(self.to_string().as_bytes());
            return;
        }
        if v == 0.0 {
            out.extend_from_slice(if v.is_sign_negative() { b"-0" } else { b"0" });
            return;
        }
        // Where the exact value ends within 19 significant digits, it can lie
        // halfway between two shortest texts, and the two libraries break
        // the tie differently (…847.25: `ryu` 847.2, the standard library
        // 847.3); such values (halves, quarters, large ones) take the
        // standard library's path. `v = odd × 2^low`.
        let bits = v.to_bits();
        let (biased, fraction) = ((bits >> 52) & 0x7ff, bits & ((1 << 52) - 1));
        let (m, e2) = if biased == 0 {
            (fraction, -1074)
        } else {
            (fraction | (1 << 52), biased as i32 - 1075)
        };
        let low = e2 + m.trailing_zeros() as i32;
        let short = if low >= 0 {
            // An integer: below 2^53 its digits are exact and unique.
            v.abs() >= 9007199254740992.0
        } else {
            // The exact value has `-low` decimals, and `|v| < 2^(e2 + 53)`:
            // its first digit stands at most `(e2 + 53) log10 2` places before
            // the point (78913 / 2^18 is log10 2 to 6 digits; one more place
            // for that rounding, so some values take the slow path unneeded).
            let places = ((e2 + 53) * 78913).div_euclid(1 << 18) + 2;
            places - low <= 19
        };
        if short {
            out.extend_from_slice(self.to_string().as_bytes());
            return;
        }
        let mut ryu = ryu::Buffer::new();
        let text = ryu.format_finite(v).as_bytes();
        let (negative, text) = match text.split_first() {
            Some((b'-', rest)) => (true, rest),
            _ => (false, text),
        };
        let (mantissa, exponent) = match text.iter().position(|&c| c == b'e') {
            Some(e) => (&text[..e], parse_exponent(&text[e + 1..])),
            None => (text, 0),
        };
        // The mantissa's digits, and how many stand before its point.
        let mut digits = [0u8; 32];
        let (mut n, mut before) = (0, None);
        for &c in mantissa {
            if c == b'.' {
                before = Some(n);
            } else {
                digits[n] = c;
                n += 1;
            }
        }
        let before = before.unwrap_or(n) as i32;
        let lead = digits[..n].iter().take_while(|&&c| c == b'0').count();
        let trail = digits[lead..n]
            .iter()
            .rev()
            .take_while(|&&c| c == b'0')
            .count();
        let d = &digits[lead..n - trail];
        // v = 0.d × 10^point.
        let point = before - lead as i32 + exponent;
        if negative {
            out.push(b'-');
        }
        let a = v.abs();
        if (1e-5..1e16).contains(&a) {
            if point <= 0 {
                out.extend_from_slice(b"0.");
                out.resize(out.len() + (-point) as usize, b'0');
                out.extend_from_slice(d);
            } else if point as usize >= d.len() {
                out.extend_from_slice(d);
                out.resize(out.len() + point as usize - d.len(), b'0');
            } else {
                out.extend_from_slice(&d[..point as usize]);
                out.push(b'.');
                out.extend_from_slice(&d[point as usize..]);
            }
        } else {
            out.push(d[0]);
            if d.len() > 1 {
                out.push(b'.');
                out.extend_from_slice(&d[1..]);
            }
            out.push(b'e');
            out.extend_from_slice(itoa::Buffer::new().format(point - 1).as_bytes());
        }
    }
}

/// The exponent `ryu` wrote after its `e`.
fn parse_exponent(text: &[u8]) -> i32 {
    let (sign, digits) = match text.split_first() {
        Some((b'-', rest)) => (-1, rest),
        _ => (1, text),
    };
    sign * digits
        .iter()
        .fold(0i32, |e, &c| 10 * e + i32::from(c - b'0'))
}

/// Appends an integer's text.
pub(crate) fn push_int(out: &mut Vec<u8>, v: impl itoa::Integer) {
    out.extend_from_slice(itoa::Buffer::new().format(v).as_bytes());
}

/// Writes `rows` rows, row `i` formatted by `row(buffer, i)`, in row order:
/// chunks of rows are formatted on every core into buffers, a bounded window
/// at a time, and each window is written on this thread while the pool
/// formats the next. The text is the same bytes as one thread writing row by
/// row, and a failing row reports the first failure in row order, as it
/// would then. Formatting, then the copy into the file, set the pace: at
/// 10^6 spheres the pore network's 5 GB of text took 43 s on one core
/// (BENCHMARKS.md).
pub(crate) fn write_rows(
    w: &mut dyn Write,
    rows: usize,
    row: impl Fn(&mut Vec<u8>, usize) -> std::io::Result<()> + Sync,
) -> std::io::Result<()> {
    use rayon::prelude::*;
    const CHUNK: usize = 1 << 13;
    // A few chunks per thread in flight, at most 32: two windows of text
    // stay within tens of MB whatever the file's size or the core count.
    let window = CHUNK * (4 * rayon::current_num_threads()).min(32);
    let format = |start: usize| -> Vec<std::io::Result<Vec<u8>>> {
        let end = rows.min(start + window);
        let chunks: Vec<usize> = (start..end).step_by(CHUNK).collect();
        chunks
            .into_par_iter()
            .map(|lo| {
                let mut text = Vec::new();
                for i in lo..end.min(lo + CHUNK) {
                    row(&mut text, i)?;
                }
                Ok(text)
            })
            .collect()
    };
    let mut texts = format(0);
    let mut start = 0;
    while start < rows {
        let next = start + window;
        let mut following = Vec::new();
        let written = rayon::in_place_scope(|s| {
            if next < rows {
                s.spawn(|_| following = format(next));
            }
            texts.drain(..).try_for_each(|text| w.write_all(&text?))
        });
        written?;
        texts = following;
        start = next;
    }
    Ok(())
}

/// A non-finite number would make the file unreadable for numpy and hide a bug;
/// refuse it with the row it is in.
pub(crate) fn finite(v: f64, what: &str, id: usize) -> std::io::Result<f64> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(Error::new(
            std::io::ErrorKind::InvalidData,
            format!("{what} of row {id} is {v}, not a finite number; refusing to write it"),
        ))
    }
}

/// Column names of `particles.csv` for dimension `D`.
pub fn particles_header<const D: usize>() -> &'static str {
    if D == 2 {
        "id,species,body,x,y,r"
    } else {
        "id,species,body,x,y,z,r"
    }
}

/// Writes `particles.csv`: one row per sphere or bead, in deposition order.
/// A bed built from `[[feeds]]` has a last column `feed`: the index of the
/// feed that placed the particle (its species').
pub fn write_particles<const D: usize>(w: &mut dyn Write, bed: &Bed<D>) -> std::io::Result<()> {
    const AXES: [&str; 3] = ["x", "y", "z"];
    let feeds = crate::bed::feed_of_species(&bed.species_info);
    let header = particles_header::<D>();
    match feeds {
        Some(_) => writeln!(w, "{header},feed")?,
        None => writeln!(w, "{header}")?,
    }
    write_rows(w, bed.len(), |w, id| {
        push_int(w, id);
        w.push(b',');
        push_int(w, bed.species[id]);
        w.push(b',');
        push_int(w, bed.bodies[id]);
        for (k, axis) in AXES.iter().enumerate().take(D) {
            w.push(b',');
            Num(finite(bed.centres[id][k], axis, id)?).push_to(w);
        }
        w.push(b',');
        Num(finite(bed.radii[id], "r", id)?).push_to(w);
        if let Some(feeds) = &feeds {
            w.push(b',');
            push_int(w, feeds[bed.species[id] as usize]);
        }
        w.push(b'\n');
        Ok(())
    })
}

/// Writes `contacts.csv`: `i,j,gap` for every touching pair.
pub fn write_contacts(w: &mut dyn Write, contacts: &Contacts) -> std::io::Result<()> {
    writeln!(w, "i,j,gap")?;
    write_rows(w, contacts.pairs.len(), |w, k| {
        let c = &contacts.pairs[k];
        let gap = Num(finite(c.gap, "gap", c.i as usize)?);
        push_int(w, c.i);
        w.push(b',');
        push_int(w, c.j);
        w.push(b',');
        gap.push_to(w);
        w.push(b'\n');
        Ok(())
    })
}

/// Writes `wall_contacts.csv`: `i,wall,gap` with wall names `floor, x0, x1, y0, y1`.
pub fn write_wall_contacts(w: &mut dyn Write, contacts: &Contacts) -> std::io::Result<()> {
    writeln!(w, "i,wall,gap")?;
    for c in &contacts.walls {
        let gap = Num(finite(c.gap, "gap", c.i as usize)?);
        writeln!(w, "{},{},{gap}", c.i, c.wall.name())?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    fn fast(v: f64) -> String {
        let mut out = Vec::new();
        Num(v).push_to(&mut out);
        String::from_utf8(out).unwrap()
    }

    #[test]
    fn the_fast_text_is_display_at_the_edges() {
        for v in [
            0.0,
            -0.0,
            1.0,
            -1.0,
            0.1,
            10.0,
            100.0,
            123.456,
            1e-5,
            9.99999e-6,
            1e16,
            9999999999999998.0,
            1e15,
            5e-324,
            -5e-324,
            f64::MAX,
            f64::MIN,
            f64::MIN_POSITIVE,
            2.5e-7,
            1.5e300,
            0.30000000000000004,
            3.6e-15,
            1e21,
            12345678901234567890.0,
            0.00001234,
            1.0 / 3.0,
        ] {
            assert_eq!(fast(v), Num(v).to_string(), "{v:e}");
        }
    }

    #[test]
    fn rows_are_written_in_order_and_the_first_failure_is_reported() {
        // Several windows on any pool, and a ragged last chunk.
        let rows = 300_007;
        let row = |w: &mut Vec<u8>, i: usize| {
            if i == 299_999 || i == 200_001 {
                return Err(Error::other(format!("row {i}")));
            }
            push_int(w, i);
            w.push(b'\n');
            Ok(())
        };
        let serial: String = (0..rows).map(|i| format!("{i}\n")).collect();
        let mut text = Vec::new();
        write_rows(&mut text, rows, |w, i| {
            push_int(w, i);
            w.push(b'\n');
            Ok(())
        })
        .unwrap();
        assert_eq!(String::from_utf8(text).unwrap(), serial);
        let mut text = Vec::new();
        let e = write_rows(&mut text, rows, row).unwrap_err();
        assert_eq!(e.to_string(), "row 200001");
        let mut text = Vec::new();
        write_rows(&mut text, 0, row).unwrap();
        assert!(text.is_empty());
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(20_000))]
        #[test]
        fn the_fast_text_is_display(bits in any::<u64>()) {
            let v = f64::from_bits(bits);
            prop_assume!(v.is_finite());
            prop_assert_eq!(fast(v), Num(v).to_string());
        }

        #[test]
        fn the_fast_text_is_display_for_short_binary_fractions(
            n in 1u64..(1 << 53),
            j in 0i32..12,
            e in -60i32..80,
        ) {
            // Halves and quarters of large integers: the exact value is a
            // tie between two shortest texts.
            let v = n as f64 / 2f64.powi(j) * 2f64.powi(e.min(0)) * 10f64.powi(e.max(0) / 8);
            prop_assert_eq!(fast(v), Num(v).to_string());
            prop_assert_eq!(fast(-v), Num(-v).to_string());
        }

        #[test]
        fn the_fast_text_is_display_for_ordinary_magnitudes(v in -1e6f64..1e6, e in -8i32..20) {
            let v = v * 10f64.powi(e);
            prop_assert_eq!(fast(v), Num(v).to_string());
        }
    }

    use super::*;
    use crate::analysis::contacts::{Contact, WallContact};
    use crate::container::{Container, Wall};
    use crate::math::Vector;

    fn bed3() -> Bed<3> {
        let mut b = Bed::new(
            Container {
                size: Vector([100.0; 3]),
                periodic: false,
            },
            Vec::new(),
        );
        b.push(Vector([0.1, 1.0 / 3.0, 10.0]), 10.0, 0);
        b.push(Vector([1e-300, 2.5, 29.999999999999996]), 20.0, 1);
        b
    }

    fn text(f: impl FnOnce(&mut dyn Write) -> std::io::Result<()>) -> String {
        let mut v = Vec::new();
        f(&mut v).unwrap();
        String::from_utf8(v).unwrap()
    }

    #[test]
    fn particles_round_trip_exactly() {
        let bed = bed3();
        let s = text(|w| write_particles(w, &bed));
        let mut lines = s.lines();
        assert_eq!(lines.next(), Some("id,species,body,x,y,z,r"));
        for (id, line) in lines.enumerate() {
            let f: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
            assert_eq!(f[0] as usize, id);
            for k in 0..3 {
                assert_eq!(f[3 + k].to_bits(), bed.centres[id][k].to_bits());
            }
            assert_eq!(f[6], bed.radii[id]);
        }
    }

    #[test]
    fn numbers_round_trip_in_every_range() {
        for v in [
            0.0,
            -0.0,
            1e-300,
            -3.552713678800501e-15,
            1e-5,
            0.1,
            1.0 / 3.0,
            12.5,
            1e16,
            1e300,
        ] {
            let t = Num(v).to_string();
            assert_eq!(t.parse::<f64>().unwrap().to_bits(), v.to_bits(), "{t}");
            assert!(t.len() <= 24, "{t}");
        }
    }

    #[test]
    fn nan_is_refused() {
        let mut bed = bed3();
        bed.centres[1][2] = f64::NAN;
        let mut v = Vec::new();
        let e = write_particles(&mut v, &bed).unwrap_err();
        assert!(e.to_string().contains("row 1"), "{e}");
    }

    #[test]
    fn contact_files() {
        let c = Contacts {
            pairs: vec![Contact {
                i: 0,
                j: 1,
                gap: -1e-12,
            }],
            walls: vec![WallContact {
                i: 0,
                wall: Wall::High(1),
                gap: 0.0,
            }],
        };
        let pairs = text(|w| write_contacts(w, &c));
        assert_eq!(pairs.lines().nth(1), Some("0,1,-1e-12"));
        let walls = text(|w| write_wall_contacts(w, &c));
        assert_eq!(walls, "i,wall,gap\n0,y1,0\n");
    }
}
