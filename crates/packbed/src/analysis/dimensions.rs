//! The dimension of every measure of `summary.json` in the bed's length unit
//! (`[analysis] length_unit`): what `packbed compare` needs to set beds
//! measured in different units side by side. Kept here, beside the summary's
//! keys ([`super::Summary`]), so that a measure added there gets its line here
//! (the integration test `compare_converts_lengths_to_the_first_groups_unit`
//! fails on a key of a full summary missing from this table).

/// The power of the length unit in a measure of `summary.json`, by its dotted
/// key as [`super::stats`] names it (`cake.d32`, `permeability.axes[0].k`,
/// `species.<name>.placed`), for a bed of `dim` dimensions: 1 for a length
/// (`cake.d32`), 2 for an area (`permeability.k_z`), −1 for a length's
/// inverse (`cake.specific_surface`), 0 for a number, a ratio or a value
/// already in SI units (`cake.k_kozeny_carman_m2`, `cake.specific_resistance`
/// in m/kg, the flow's viscosity in its own unit). `None` for a key whose
/// dimension is not known here (the fragmentation's forces, a key of a later
/// version): its values mean different things in different units.
pub fn length_power(key: &str, dim: u8) -> Option<i32> {
    let key = normalised(key);
    let k = key.as_str();
    // Whole families of numbers, ratios and counts.
    const NUMBERS: [&str; 5] = [
        "packing.",
        "coordination.",
        "counts.",
        "orientation.",
        "species.*.",
    ];
    // Lengths among the packing's numbers: the profile's slabs and heights,
    // the pair correlation's distances.
    if matches!(
        k,
        "packing.profile.slab"
            | "packing.profile.z[]"
            | "packing.pair_correlation.bin"
            | "packing.pair_correlation.r[]"
            | "packing.heap.apex_height"
    ) {
        return Some(1);
    }
    if NUMBERS.iter().any(|p| k.starts_with(p)) {
        return Some(0);
    }
    let power = match k {
        // The cake (and the same over the whole cake).
        "cake.porosity" | "cake.whole.porosity" => 0,
        "cake.d32" | "cake.whole.d32" => 1,
        "cake.specific_surface" | "cake.whole.specific_surface" => -1,
        "cake.surface_per_bed_volume" | "cake.whole.surface_per_bed_volume" => -1,
        "cake.k_kozeny_carman" | "cake.whole.k_kozeny_carman" => 2,
        "cake.height" | "cake.solids_per_area" => 1,
        // Already in SI units: m², kg/m², m/kg.
        "cake.k_kozeny_carman_m2" | "cake.solids_mass_per_area" | "cake.specific_resistance" => 0,
        // Pores and constrictions of the slab.
        "pores.d_c35" => 1,
        "pores.network_porosity"
        | "pores.network_pores"
        | "pores.network_throats"
        | "pores.hidden_particles"
        | "pores.clamped_cells"
        | "pores.overlap_inexact_cells"
        | "pores.overlap_inexact_throats"
        | "pores.body_radius_undefined"
        | "pores.body_radius.count"
        | "pores.constriction_radius.count" => 0,
        _ if k.starts_with("pores.body_radius.") || k.starts_with("pores.constriction_radius.") => {
            1
        }
        // The network's flow: k in length², the flux under a unit gradient
        // through the section (an area in 3D, a length per unit depth in 2D).
        "permeability.k_x" | "permeability.k_y" | "permeability.k_z" | "permeability.axes[].k" => 2,
        "permeability.axes[].flux" => i32::from(dim) + 1,
        "permeability.k_over_d32_squared"
        | "permeability.k_over_kozeny_carman"
        | "permeability.anisotropy"
        | "permeability.anisotropy_uncertainty"
        | "permeability.conductance_factor"
        // In the viscosity's own unit, which `length_unit` does not set.
        | "permeability.viscosity"
        | "permeability.throats_merged"
        | "permeability.imbalance"
        | "permeability.axes[].imbalance"
        | "permeability.axes[].pores" => 0,
        // The drainage: pressures reduced by d32 or in Pa, saturations,
        // counts, N/m and degrees: all free of the bed's unit but these.
        "drainage.d32" => 1,
        "drainage.pore_volume" => i32::from(dim),
        _ if k.starts_with("drainage.") || k.starts_with("transport.") => 0,
        // Percolation: bodies, chains (lengths counted in bodies), flags.
        "percolation.large_radius" => 1,
        _ if k.starts_with("percolation.") => 0,
        // Segregation.
        "segregation.slab" | "segregation.bed_height" => 1,
        "segregation.bottom_fraction_all" => 0,
        // Voids of a 2D bed: areas.
        "voids.min_area" | "voids.mean_area" | "voids.max_area" | "voids.total_area" => 2,
        "voids.count" | "voids.mean_area_scaled" | "voids.mean_sides" => 0,
        // The size distribution: diameters, and percentages and spans.
        "psd.requested.d10" | "psd.requested.d50" | "psd.requested.d90" => 1,
        "psd.placed.d10" | "psd.placed.d50" | "psd.placed.d90" => 1,
        "psd.table[].radius" | "psd.table[].diameter" => 1,
        "psd.requested.span" | "psd.placed.span" => 0,
        _ if k.starts_with("psd.table[].") && k.ends_with("_percent_passing") => 0,
        // How far the placed curve is from the requested, and where.
        "psd.departure.at_diameter" => 1,
        _ if k.starts_with("psd.departure.") => 0,
        // The filter medium's capture: bodies, fractions and ratios, and
        // these lengths (sizes, heights, depths) in the bed's unit.
        "capture.medium_lift"
        | "capture.medium_bottom"
        | "capture.medium_surface"
        | "capture.x50"
        | "capture.classes[].d_lo"
        | "capture.classes[].d_hi"
        | "capture.constrictions[].d_lo"
        | "capture.constrictions[].d_hi"
        | "capture.depth_profile[].depth_lo"
        | "capture.depth_profile[].depth_hi"
        | "capture.criteria.medium_d15"
        | "capture.criteria.slurry_d85"
        | "capture.criteria.slurry_d85_by_surface"
        | "capture.criteria.constriction_diameter[]"
        | "capture.criteria.kenney_constriction" => 1,
        _ if k.starts_with("capture.") => 0,
        // The filtration: in SI throughout, each key naming its unit.
        _ if k.starts_with("filtration.") => 0,
        _ => return None,
    };
    Some(power)
}

/// The unit of a measure of the filtration (`filtration.*`, in SI, each key
/// naming its unit: `_m_per_kg` is m/kg) or of the capture (`capture.*`:
/// `length`, the bed's length unit, for its sizes, heights and depths;
/// `bodies` for counts; `1` for fractions and ratios), as the ensemble,
/// sweep and comparison tables print it beside the key. `None` for any
/// other key: those tables print no unit for it.
pub fn filtration_unit(key: &str, length: &str) -> Option<String> {
    let key = normalised(key);
    let k = key.as_str();
    if let Some(rest) = k.strip_prefix("filtration.") {
        // Longest suffix first: `_m3_per_m2` before `_per_m2`, `_per_m`
        // before `_m`.
        const SI: [(&str, &str); 8] = [
            ("_m_per_kg", "m/kg"),
            ("_m3_per_m2", "m³/m²"),
            ("_kg_per_m2", "kg/m²"),
            ("_per_m", "1/m"),
            ("_pa", "Pa"),
            ("_s", "s"),
            ("_m", "m"),
            ("ruth_departure", "1"),
        ];
        return SI
            .iter()
            .find(|(suffix, _)| rest.ends_with(suffix))
            .map(|(_, unit)| unit.to_string());
    }
    if !k.starts_with("capture.") {
        return None;
    }
    Some(match length_power(k, 3) {
        Some(1) => length.to_string(),
        _ if k.ends_with("fraction")
            || k.ends_with("efficiency")
            || k.ends_with("ratio")
            || k.ends_with("_finer") =>
        {
            "1".into()
        }
        _ => "bodies".into(),
    })
}

/// `key` with its indices as `[]` and a species' name as `*`.
fn normalised(key: &str) -> String {
    let mut out = String::with_capacity(key.len());
    let mut in_index = false;
    for c in key.chars() {
        match c {
            '[' => {
                in_index = true;
                out.push('[');
            }
            ']' => {
                in_index = false;
                out.push(']');
            }
            _ if in_index => {}
            _ => out.push(c),
        }
    }
    // A species' name may hold dots: its field is the key's last part.
    match out.strip_prefix("species.") {
        Some(rest) => match rest.rsplit_once('.') {
            Some((_, field)) => format!("species.*.{field}"),
            None => out,
        },
        None => out,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lengths_areas_and_numbers() {
        assert_eq!(length_power("cake.d32", 3), Some(1));
        assert_eq!(length_power("packing.profile.z[4]", 3), Some(1));
        assert_eq!(length_power("packing.pair_correlation.r[0]", 2), Some(1));
        assert_eq!(length_power("packing.pair_correlation.g[0]", 2), Some(0));
        assert_eq!(length_power("packing.profile.fraction[4]", 3), Some(0));
        assert_eq!(length_power("cake.specific_surface", 3), Some(-1));
        assert_eq!(length_power("permeability.k_z", 3), Some(2));
        assert_eq!(length_power("permeability.axes[2].k", 3), Some(2));
        assert_eq!(length_power("permeability.axes[0].flux", 3), Some(4));
        assert_eq!(length_power("permeability.axes[0].flux", 2), Some(3));
        assert_eq!(length_power("cake.specific_resistance", 3), Some(0));
        assert_eq!(length_power("species.batch A. sieved.placed", 3), Some(0));
        assert_eq!(length_power("psd.table[12].diameter", 3), Some(1));
        assert_eq!(
            length_power("pores.body_radius.by_void_volume.p35", 3),
            Some(1)
        );
        assert_eq!(length_power("fragmentation.max_force", 3), None);
        assert_eq!(length_power("cake.something_new", 3), None);
        assert_eq!(length_power("capture.x50", 3), Some(1));
        assert_eq!(length_power("capture.classes[3].d_lo", 3), Some(1));
        assert_eq!(length_power("capture.classes[3].fed", 3), Some(0));
        assert_eq!(
            length_power("capture.criteria.constriction_diameter[1]", 3),
            Some(1)
        );
        assert_eq!(length_power("capture.criteria.terzaghi_ratio", 3), Some(0));
        assert_eq!(length_power("capture.passed_fraction", 3), Some(0));
        assert_eq!(length_power("filtration.alpha_fit_m_per_kg", 3), Some(0));
        assert_eq!(length_power("filtration.final.cake_height_m", 3), Some(0));
    }

    #[test]
    fn units_of_the_filtration_and_the_capture() {
        let unit = |k: &str| filtration_unit(k, "µm");
        for (key, want) in [
            ("filtration.alpha_fit_m_per_kg", "m/kg"),
            ("filtration.alpha_network_m_per_kg", "m/kg"),
            ("filtration.r_medium_fit_per_m", "1/m"),
            ("filtration.r_medium_clogged_per_m", "1/m"),
            ("filtration.ruth_departure", "1"),
            ("filtration.final.time_s", "s"),
            ("filtration.final.volume_m3_per_m2", "m³/m²"),
            ("filtration.final.mass_kg_per_m2", "kg/m²"),
            ("filtration.final.cake_height_m", "m"),
            ("filtration.final.pressure_pa", "Pa"),
            ("filtration.checkpoints[3].r_cake_per_m", "1/m"),
            ("capture.x50", "µm"),
            ("capture.criteria.medium_d15", "µm"),
            ("capture.passed_fraction", "1"),
            ("capture.classes[2].grade_efficiency", "1"),
            ("capture.criteria.indraratna_ratio", "1"),
            ("capture.lodged", "bodies"),
            ("capture.constrictions[4].d_hi", "µm"),
            ("capture.constrictions[4].constrictions_finer", "1"),
            ("capture.constrictions[4].slurry", "bodies"),
            ("filtration.r_medium_fit_se_per_m", "1/m"),
        ] {
            assert_eq!(unit(key).as_deref(), Some(want), "{key}");
        }
        assert_eq!(unit("cake.d32"), None);
        assert_eq!(unit("packing.global"), None);
    }
}
