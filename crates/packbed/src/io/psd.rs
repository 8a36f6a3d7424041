//! `psd.csv`: the size distribution placed against the one requested, one row
//! per size: diameters and radii, mass and number percent passing
//! (`docs/reference/formats.md`, "psd.csv").

use crate::analysis::psd::PsdSummary;
use std::io::Write;

/// The file's name.
pub const PSD_FILE: &str = "psd.csv";

/// Writes the table of `psd` as CSV with a header of its column names.
pub fn write_psd(w: &mut dyn Write, psd: &PsdSummary) -> std::io::Result<()> {
    let mut out = csv::Writer::from_writer(w);
    for row in &psd.table {
        out.serialize(row).map_err(std::io::Error::other)?;
    }
    out.flush()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::psd::{PsdRow, PsdStats};

    #[test]
    fn the_header_names_the_columns() {
        let stats = PsdStats {
            d10: 1.0,
            d50: 2.0,
            d90: 3.0,
            span: 1.0,
        };
        let table = vec![PsdRow {
            radius: 0.5,
            diameter: 1.0,
            requested_mass_percent_passing: 10.0,
            placed_mass_percent_passing: 12.5,
            requested_number_percent_passing: 50.0,
            placed_number_percent_passing: 60.0,
        }];
        let psd = PsdSummary {
            requested: stats,
            placed: stats,
            departure: crate::analysis::psd::departure(&table, 10),
            table,
        };
        let mut buf = Vec::new();
        write_psd(&mut buf, &psd).unwrap();
        assert_eq!(
            String::from_utf8(buf).unwrap(),
            "radius,diameter,requested_mass_percent_passing,placed_mass_percent_passing,\
             requested_number_percent_passing,placed_number_percent_passing\n\
             0.5,1.0,10.0,12.5,50.0,60.0\n"
        );
    }
}
