//! Pictures, plots, exports and readers: parse what the writers wrote.

use packbed::render::{self, text_width, ColorBy, Cut, RenderOptions, View};
use packbed::Container;
use packbed::Error;
use packbed::ExportFormat as Format;
use packbed::Vector;
use packbed::{read_bed, BoxHint};
use packbed::{AnyBed, Bed};
use std::path::{Path, PathBuf};
use tiny_skia::Pixmap;

fn scratch(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("packbed-render-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A small deterministic 2D bed: a floor row of large discs, smalls on top.
fn bed2() -> Bed<2> {
    let mut bed = Bed::new(
        Container {
            size: Vector([200.0, 150.0]),
            periodic: false,
        },
        Vec::new(),
    );
    for k in 0..5 {
        bed.push(Vector([20.0 + 40.0 * k as f64, 20.0]), 20.0, 0);
    }
    for k in 0..4 {
        let x = 40.0 + 40.0 * k as f64;
        let y = 20.0 + (30f64.powi(2) - 20f64.powi(2)).sqrt();
        bed.push(Vector([x, y]), 10.0, 1);
    }
    bed
}

/// Pseudo-random 3D bed (no physics needed for I/O), with a two-bead body.
fn bed3(periodic: bool) -> Bed<3> {
    let mut bed = Bed::new(
        Container {
            size: Vector([100.0, 80.0, 120.0]),
            periodic,
        },
        Vec::new(),
    );
    let mut s: u64 = 12345;
    let mut next = || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    for _ in 0..50 {
        let mut c = Vector([100.0 * next(), 80.0 * next(), 120.0 * next()]);
        let r = 1.0 + 9.0 * next() / 3.0;
        // Inside the box: the reader refuses particles sticking out of it.
        for k in 0..3 {
            c[k] = c[k].clamp(r, bed.container.size[k] - r);
        }
        bed.push(c, r, (next() * 3.0) as u32);
    }
    let body = bed.bodies.last().unwrap() + 1;
    bed.push_bead(Vector([10.0, 10.0, 10.0]), 2.5, 3, body);
    bed.push_bead(Vector([12.5, 10.0, 10.0]), 2.5, 3, body);
    bed
}

fn attr(tag: &str, name: &str) -> f64 {
    let key = format!(" {name}=\"");
    let start = tag.find(&key).unwrap() + key.len();
    let end = start + tag[start..].find('"').unwrap();
    tag[start..end].parse().unwrap()
}

#[test]
fn svg_has_one_exact_circle_per_disc() {
    let bed = bed2();
    let svg = render::render_svg(&AnyBed::D2(bed.clone()), &RenderOptions::default()).unwrap();
    let circles: Vec<&str> = svg
        .lines()
        .filter(|l| l.starts_with("<circle class=\"particle\""))
        .collect();
    assert_eq!(circles.len(), bed.len());
    for (i, c) in circles.iter().enumerate() {
        assert_eq!(attr(c, "cx"), bed.centres[i][0]);
        assert_eq!(attr(c, "cy"), bed.centres[i][1]);
        assert_eq!(attr(c, "r"), bed.radii[i]);
    }
    // The bed coordinates sit under a y-flipping transform.
    assert!(svg.contains("<g transform=\"matrix("));
    assert!(svg.trim_end().ends_with("</svg>"));
}

#[test]
fn svg_draws_a_chain_as_one_body() {
    let mut bed = bed2();
    let b = bed.bodies.last().unwrap() + 1;
    bed.push_bead(Vector([100.0, 100.0]), 5.0, 2, b);
    bed.push_bead(Vector([105.0, 100.0]), 5.0, 2, b);
    let svg = render::render_svg(&AnyBed::D2(bed.clone()), &RenderOptions::default()).unwrap();
    assert_eq!(svg.matches("class=\"particle\"").count(), bed.len());
    // Outlines under both beads, fills without outline on top.
    let outline = svg.find("class=\"bead-outline\"").unwrap();
    let last_fill = svg.rfind("class=\"particle\"").unwrap();
    assert!(outline < last_fill);
    assert_eq!(svg.matches("class=\"bead-outline\"").count(), 2);
    let fills: Vec<&str> = svg
        .lines()
        .filter(|l| l.contains("class=\"particle\""))
        .collect();
    assert!(!fills[fills.len() - 1].contains("stroke="));
}

/// The darkest pixel within one pixel of `(x, y)` (lines are antialiased).
fn darkest(p: &Pixmap, x: f64, y: f64) -> (u8, u8, u8) {
    let mut best = (255, 255, 255);
    for dy in -1..=1 {
        for dx in -1..=1 {
            let c = rgb(p, x + dx as f64, y + dy as f64);
            if (c.0 as u32 + c.1 as u32 + c.2 as u32)
                < (best.0 as u32 + best.1 as u32 + best.2 as u32)
            {
                best = c;
            }
        }
    }
    best
}

fn rgb(p: &Pixmap, x: f64, y: f64) -> (u8, u8, u8) {
    let c = p.pixel(x.round() as u32, y.round() as u32).unwrap();
    (c.red(), c.green(), c.blue())
}

#[test]
fn png_2d_has_the_size_the_box_and_the_discs_where_they_should_be() {
    let bed = bed2();
    let opts = RenderOptions {
        width: 900,
        height: 700,
        ..RenderOptions::default()
    };
    let png = render::render_png(&AnyBed::D2(bed.clone()), &opts).unwrap();
    let p = Pixmap::decode_png(&png).unwrap();
    assert_eq!((p.width(), p.height()), (900, 700));
    let w = render::placement(&bed, &opts).unwrap();
    // Disc centres carry their species colour.
    for i in 0..bed.len() {
        let (x, y) = w.apply(bed.centres[i][0], bed.centres[i][1]);
        let c = render::categorical(bed.species[i] as usize);
        assert_eq!(rgb(&p, x, y), (c.0, c.1, c.2), "disc {i}");
    }
    // The box outline: dark on the right wall at mid-height and on the roof.
    let (x, y) = w.apply(200.0, 120.0);
    let c = darkest(&p, x, y);
    assert!(c.0 < 80 && c.1 < 80 && c.2 < 80, "right wall {c:?}");
    let (x, y) = w.apply(100.0, 150.0);
    let c = darkest(&p, x, y);
    assert!(c.0 < 80 && c.1 < 80 && c.2 < 80, "roof {c:?}");
    // Empty space inside the box is white.
    let (x, y) = w.apply(100.0, 130.0);
    assert_eq!(rgb(&p, x, y), (255, 255, 255));
    // Outside the picture area (bottom right corner) is white too.
    assert_eq!(rgb(&p, 895.0, 695.0), (255, 255, 255));
}

#[test]
fn coordination_colours_follow_the_contacts() {
    let bed = bed2();
    let opts = RenderOptions {
        color: ColorBy::Coordination,
        ..RenderOptions::default()
    };
    let contacts = packbed::find_contacts(&bed, 1e-6);
    let pal = render::palette(&bed, &opts.color, Some(&contacts)).unwrap();
    let z = packbed::coordination(&bed, &contacts);
    // Floor discs: two neighbours in the row (one at the ends) plus smalls above.
    assert_eq!(z, vec![2, 4, 4, 4, 2, 2, 2, 2, 2]);
    assert_eq!(pal.colours[0], render::viridis(0.5));
    assert_eq!(pal.colours[1], render::viridis(1.0));
    let labels: Vec<&str> = pal.legend.iter().map(|l| l.1.as_str()).collect();
    assert_eq!(labels, ["2", "4"]);
}

#[test]
fn chain_colours_mark_the_spanning_clusters_of_the_percolation() {
    use packbed::LargeRule;
    use packbed::{percolation, PercolationOptions};
    let bed = bed2();
    let contacts = packbed::find_contacts(&bed, 1e-6);
    let c = render::chain_classes(&bed, &contacts, LargeRule::Median);
    // The floor row of large discs spans x0 to x1; the smalls are backdrop.
    assert_eq!(c.class, vec![0, 0, 0, 0, 0, 2, 2, 2, 2]);
    assert!(c.labels[0].contains("wall-to-wall"));
    let p = percolation(&bed, &contacts, &PercolationOptions::default());
    assert_eq!((p.large_bodies, p.spanning_clusters), (5, 1));
    // Without the middle disc the row no longer spans, here or in the analysis.
    let mut broken = bed.clone();
    broken.radii[2] = 19.0;
    let contacts = packbed::find_contacts(&broken, 1e-6);
    let c = render::chain_classes(&broken, &contacts, LargeRule::Radius(20.0));
    assert_eq!(&c.class[..5], &[1, 1, 2, 1, 1]);
    let p = percolation(&broken, &contacts, &PercolationOptions::default());
    assert_eq!(p.spanning_clusters, 0);
    // Periodic sides: the row closes round the seam, a cluster that wraps.
    let mut periodic = bed;
    periodic.container.periodic = true;
    let contacts = packbed::find_contacts(&periodic, 1e-6);
    let c = render::chain_classes(&periodic, &contacts, LargeRule::Median);
    assert_eq!(c.class, vec![0, 0, 0, 0, 0, 2, 2, 2, 2]);
    assert!(c.labels[0].contains("wrapping"));
    let p = percolation(&periodic, &contacts, &PercolationOptions::default());
    assert_eq!((p.criterion.as_str(), p.spanning_clusters), ("wraps", 1));
}

fn one_sphere() -> Bed<3> {
    let mut bed = Bed::new(
        Container {
            size: Vector([10.0, 10.0, 10.0]),
            periodic: false,
        },
        Vec::new(),
    );
    bed.push(Vector([5.0, 5.0, 5.0]), 2.0, 0);
    bed
}

#[test]
fn png_3d_sphere_seen_from_above() {
    let opts = RenderOptions {
        width: 600,
        height: 500,
        view: View {
            azimuth: 0.0,
            elevation: 90.0,
        },
        ..RenderOptions::default()
    };
    let png = render::render_png(&AnyBed::D3(one_sphere()), &opts).unwrap();
    let p = Pixmap::decode_png(&png).unwrap();
    assert_eq!((p.width(), p.height()), (600, 500));
    // Find the blue disc: its bounding box is square and about 2/5 of the box's.
    let blue = render::categorical(0);
    let (mut x0, mut x1, mut y0, mut y1) = (u32::MAX, 0, u32::MAX, 0);
    let mut box_ink = 0;
    for y in 0..p.height() {
        // Left of the legend (its swatch is blue too).
        for x in 0..420 {
            let c = p.pixel(x, y).unwrap();
            // Blue dominant, shaded: the sphere.
            if c.blue() as i32 > c.red() as i32 + 20 {
                x0 = x0.min(x);
                x1 = x1.max(x);
                y0 = y0.min(y);
                y1 = y1.max(y);
            }
            if c.red() < 60 && c.green() < 60 && c.blue() < 60 {
                box_ink += 1;
            }
        }
    }
    let (dw, dh) = ((x1 - x0) as f64, (y1 - y0) as f64);
    assert!((dw - dh).abs() <= 3.0, "{dw} × {dh}");
    // The box (side 10) fills the picture height between title and scale bar.
    assert!(dw > 60.0 && dw < 250.0, "{dw}");
    // Centre of the disc, normal towards the camera: blue (0, 114, 178) times
    // ambient 0.45 + diffuse 0.55 × 0.661 (the light's height), plus a specular
    // 0.25 × 255 × 0.911^40: blue ≈ 144.8 + 1.6.
    let c = p.pixel((x0 + x1) / 2, (y0 + y1) / 2).unwrap();
    assert!(c.red() < 8 && c.blue().abs_diff(146) <= 5, "{c:?}");
    assert!(
        c.green().abs_diff((114.0f64 * 0.8133 + 1.6) as u8) <= 5,
        "{c:?}"
    );
    let _ = blue;
    // Box outline and text drawn in dark ink.
    assert!(box_ink > 500, "{box_ink}");
    // Corner pixel: white paper.
    assert_eq!(rgb(&p, 2.0, 498.0), (255, 255, 255));
}

#[test]
fn png_3d_is_the_same_whatever_the_thread_count() {
    let bed = bed3(false);
    let opts = RenderOptions {
        width: 400,
        height: 300,
        cut: Cut::Half,
        ..RenderOptions::default()
    };
    let any = AnyBed::D3(bed);
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| render::render_png(&any, &opts).unwrap());
    let two = rayon::ThreadPoolBuilder::new()
        .num_threads(3)
        .build()
        .unwrap()
        .install(|| render::render_png(&any, &opts).unwrap());
    assert!(one == two);
}

#[test]
fn cut_away_removes_the_front() {
    // Two spheres on the line of sight of a front view: the cut shows the back one.
    let mut bed = Bed::new(
        Container {
            size: Vector([10.0, 10.0, 10.0]),
            periodic: false,
        },
        Vec::new(),
    );
    bed.push(Vector([5.0, 2.0, 5.0]), 1.5, 0);
    bed.push(Vector([5.0, 8.0, 5.0]), 1.5, 1);
    let front = View {
        azimuth: 0.0,
        elevation: 0.0,
    };
    let colour_at_centre = |cut: Cut| {
        let opts = RenderOptions {
            width: 500,
            height: 500,
            view: front,
            cut,
            ..RenderOptions::default()
        };
        let p = Pixmap::decode_png(&render::render_png(&AnyBed::D3(bed.clone()), &opts).unwrap())
            .unwrap();
        // The spheres are at the centre of the box's projection.
        let (mut sx, mut sy, mut n) = (0u64, 0u64, 0u64);
        for y in 0..500 {
            for x in 0..400 {
                let c = p.pixel(x, y).unwrap();
                if c.red().abs_diff(c.blue()) > 60 {
                    sx += x as u64;
                    sy += y as u64;
                    n += 1;
                }
            }
        }
        let c = p.pixel((sx / n) as u32, (sy / n) as u32).unwrap();
        (c.red(), c.blue())
    };
    let (r, b) = colour_at_centre(Cut::None);
    assert!(b > r, "front sphere is species 0 (blue): {r} {b}");
    let (r, b) = colour_at_centre(Cut::Half);
    assert!(r > b, "behind the cut: species 1 (orange): {r} {b}");
    let (r, b) = colour_at_centre(Cut::Slab {
        axis: 1,
        lo: 0.0,
        hi: 4.0,
    });
    assert!(b > r);
}

#[test]
fn svg_of_a_3d_bed_is_refused_and_bad_sizes_too() {
    let any = AnyBed::D3(one_sphere());
    assert!(render::render_svg(&any, &RenderOptions::default()).is_err());
    let tiny = RenderOptions {
        width: 10,
        ..RenderOptions::default()
    };
    assert!(render::render_png(&any, &tiny).is_err());
    let bad_view = RenderOptions {
        view: View {
            azimuth: 0.0,
            elevation: 120.0,
        },
        ..RenderOptions::default()
    };
    assert!(render::render_png(&any, &bad_view).is_err());
}

/// Every `<text>` of an SVG lies inside the page (width from the font metrics).
fn assert_no_clipped_text(svg: &str, w: f64, h: f64) {
    let mut n = 0;
    for l in svg.lines().filter(|l| l.starts_with("<text")) {
        n += 1;
        let (x, y, size) = (attr(l, "x"), attr(l, "y"), attr(l, "font-size"));
        let text = &l[l.find('>').unwrap() + 1..l.rfind("</text>").unwrap()];
        let tw = text_width(text, size);
        let (a, b) = if l.contains("text-anchor=\"middle\"") {
            (-tw / 2.0, tw / 2.0)
        } else if l.contains("text-anchor=\"end\"") {
            (-tw, 0.0)
        } else {
            (0.0, tw)
        };
        if l.contains("rotate(-90") {
            assert!(
                y - b >= 0.0 && y - a <= h && x - size >= 0.0 && x <= w,
                "{l}"
            );
        } else {
            assert!(
                x + a >= 0.0 && x + b <= w && y - size >= 0.0 && y + 0.3 * size <= h,
                "{l}"
            );
        }
    }
    assert!(n > 3);
}

#[test]
fn plots_have_their_labels_inside_the_page() {
    let bed = bed2();
    let contacts = packbed::find_contacts(&bed, 1e-6);
    let z = packbed::coordination(&bed, &contacts);
    let profile = packbed::profile(&bed, 5.0);
    let plots = [
        render::coordination_histogram(&bed, &z),
        render::packing_profile(&profile, 5.0, Some(0.8), None),
        render::regional_packing(&[
            ("floor".into(), 0.55, Some(0.02)),
            ("roof".into(), 0.4, Some(0.03)),
            ("wall".into(), 0.5, Some(0.01)),
            ("centre".into(), 0.6, Some(0.01)),
        ]),
        render::chain_angle_histogram(&[-30.0, 2.0, 4.0, 88.0], 2, packbed::AngleFrom::Vertical),
    ];
    for plot in &plots {
        for (w, h) in [(1000, 700), (500, 350)] {
            let svg = plot.to_svg(w, h).unwrap();
            assert_no_clipped_text(&svg, w as f64, h as f64);
            assert!(svg.contains(&plot.title.replace('&', "&amp;")) || svg.contains("<text"));
            let png = Pixmap::decode_png(&plot.to_png(w, h).unwrap()).unwrap();
            assert_eq!((png.width(), png.height()), (w, h));
        }
    }
    // The histogram: all particles, then one group per species, in percent.
    let svg = plots[0].to_svg(1000, 700).unwrap();
    assert!(svg.contains(">all particles<") && svg.contains(">species 1<"));
    // Bars of species 0 (5 discs: z = 2, 4, 4, 4, 2): 40 % at 2, 60 % at 4.
    let bars = svg
        .lines()
        .filter(|l| l.starts_with("<rect") && l.contains("fill=\"#e69f00\""))
        .count();
    // One orange (species 0) bar per category 0..=4, and the legend's swatch.
    assert_eq!(bars, 6);
}

#[test]
fn bed_pictures_have_their_labels_inside_the_page() {
    for (w, h) in [(1200, 1000), (400, 300)] {
        let opts = RenderOptions {
            width: w,
            height: h,
            ..RenderOptions::default()
        };
        let svg = render::render_svg(&AnyBed::D2(bed2()), &opts).unwrap();
        assert_no_clipped_text(&svg, w as f64, h as f64);
    }
}

fn same_particles<const D: usize>(a: &Bed<D>, b: &Bed<D>) {
    assert_eq!(a.len(), b.len());
    assert_eq!(a.centres, b.centres);
    assert_eq!(a.radii, b.radii);
    assert_eq!(a.species, b.species);
    assert_eq!(a.bodies, b.bodies);
    assert_eq!(a.container, b.container);
}

fn export_and_read<const D: usize>(dir: &Path, bed: &Bed<D>, f: Format) -> AnyBed {
    let z = vec![0u32; bed.len()];
    let path = dir.join(f.file_name());
    let mut file = std::fs::File::create(&path).unwrap();
    f.write(&mut file, bed, &z).unwrap();
    drop(file);
    read_bed(&path, None).unwrap()
}

#[test]
fn exports_round_trip_through_the_reader() {
    let dir = scratch("roundtrip");
    for f in [Format::Vtk, Format::Dump, Format::Xyz] {
        for periodic in [false, true] {
            let bed = bed3(periodic);
            match export_and_read(&dir, &bed, f) {
                AnyBed::D3(b) => same_particles(&bed, &b),
                AnyBed::D2(_) => panic!("{f:?}: 3D read back as 2D"),
            }
            let mut b2 = bed2();
            b2.container.periodic = periodic;
            match export_and_read(&dir, &b2, f) {
                AnyBed::D2(b) => same_particles(&b2, &b),
                AnyBed::D3(_) => panic!("{f:?}: 2D read back as 3D"),
            }
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn dump_has_the_lammps_layout() {
    let mut buf = Vec::new();
    let bed = bed3(true);
    Format::Dump
        .write(&mut buf, &bed, &vec![3; bed.len()])
        .unwrap();
    let text = String::from_utf8(buf).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], "ITEM: TIMESTEP");
    assert_eq!(lines[3], bed.len().to_string());
    assert_eq!(lines[4], "ITEM: BOX BOUNDS pp pp ff");
    assert_eq!(lines[5..8], ["0 100", "0 80", "0 120"]);
    assert!(lines[8].starts_with("ITEM: ATOMS id type x y z radius"));
    assert_eq!(lines.len(), 9 + bed.len());
    let first: Vec<&str> = lines[9].split_whitespace().collect();
    assert_eq!(first[0], "1");
    assert_eq!(first[1], (bed.species[0] + 1).to_string());
}

#[test]
fn packbed_csv_reads_with_the_box_from_summary_json() {
    let dir = scratch("csv");
    let bed = bed2();
    let (contacts, analysis) = packbed::analyze(&bed, 1e-6);
    let config = packbed::Config::default();
    let summary = packbed::RunSummary::new(
        &config,
        &bed,
        &packbed::DepositReport::default(),
        &analysis,
        packbed::Timing::default(),
    );
    packbed::write_run(&dir, &bed, &contacts, &summary).unwrap();
    match read_bed(&dir.join("particles.csv"), None).unwrap() {
        AnyBed::D2(b) => same_particles(&bed, &b),
        _ => panic!("2D"),
    }
    // Without summary.json the box must be given.
    std::fs::remove_file(dir.join("summary.json")).unwrap();
    let e = read_bed(&dir.join("particles.csv"), None).unwrap_err();
    assert!(e.to_string().contains("give the box (W,H)"), "{e}");
    let hint = BoxHint {
        size: vec![200.0, 150.0],
        periodic: false,
    };
    match read_bed(&dir.join("particles.csv"), Some(&hint)).unwrap() {
        AnyBed::D2(b) => same_particles(&bed, &b),
        _ => panic!("2D"),
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn plain_tables_with_and_without_header() {
    let dir = scratch("plain");
    let hint3 = BoxHint {
        size: vec![10.0, 10.0, 10.0],
        periodic: true,
    };
    let p = dir.join("a.txt");
    std::fs::write(&p, "# x y z r\n1 2 3 0.5\n\n4 5 6 0.25\n").unwrap();
    let AnyBed::D3(b) = read_bed(&p, Some(&hint3)).unwrap() else {
        panic!("3D")
    };
    assert_eq!(b.centres[1], Vector([4.0, 5.0, 6.0]));
    assert_eq!(b.radii, vec![0.5, 0.25]);
    assert_eq!(b.bodies, vec![0, 1]);
    assert!(b.container.periodic);
    let p = dir.join("b.csv");
    std::fs::write(&p, "radius,x,y,type\n1.5,3,4,2\n").unwrap();
    let hint2 = BoxHint {
        size: vec![10.0, 10.0],
        periodic: false,
    };
    let AnyBed::D2(b) = read_bed(&p, Some(&hint2)).unwrap() else {
        panic!("2D")
    };
    assert_eq!(
        (b.centres[0], b.radii[0], b.species[0]),
        (Vector([3.0, 4.0]), 1.5, 2)
    );
    // A 3D box for 2D particles is refused.
    assert!(read_bed(&p, Some(&hint3))
        .unwrap_err()
        .to_string()
        .contains("2D"));
    std::fs::remove_dir_all(&dir).unwrap();
}

fn data_error(text: &str, name: &str, hint: Option<&BoxHint>) -> (usize, String) {
    let dir = scratch(&format!("err-{}", name.replace('.', "-")));
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    let e = read_bed(&p, hint).unwrap_err();
    std::fs::remove_dir_all(&dir).unwrap();
    match e {
        Error::Data {
            path,
            line,
            message,
        } => {
            assert_eq!(path, p);
            (line, message)
        }
        other => panic!("{other}"),
    }
}

#[test]
fn bad_files_are_refused_with_file_and_line() {
    let h = BoxHint {
        size: vec![10.0, 10.0, 10.0],
        periodic: false,
    };
    let cases: [(&str, &str, usize, &str); 12] = [
        ("", "e.txt", 1, "empty"),
        ("1 1 1 1e-40\n", "tiny.txt", 1, "choose other units"),
        ("1 1 1 1\n5 5 5 6\n", "wide.txt", 2, "larger than the box"),
        ("1 1 1 1\n5 5 5 1e300\n", "huge.txt", 2, "lengths from 1e0 to 1e300"),
        ("x,y,z,r\n1,2,3,1\n1,2,x,1\n", "c.csv", 3, "not a number"),
        ("x,y,z,r\n1,2,3,1\n1,2,3,NaN\n", "n.csv", 3, "not a finite number"),
        ("1 2 3 1\n1 2 3 -1\n", "neg.txt", 2, "must be > 0"),
        ("x,y,r\n1,2\n", "short.csv", 2, "columns"),
        ("x,z,r\n1,2,3\n", "noy.csv", 1, "x and y"),
        (
            "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n99999999999999\n",
            "big.dump",
            4,
            "more than",
        ),
        (
            "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n3\nITEM: BOX BOUNDS ff ff ff\n0 1\n0 1\n0 1\nITEM: ATOMS id type x y z radius\n1 1 0.5 0.5 0.5 0.1\n",
            "short.dump",
            11,
            "ends after 1 of 3",
        ),
        (
            "2\nLattice=\"1 0 0 0 1 0 0 0 1\" Properties=species:S:1:pos:R:3:radius:R:1\nA 0 0 0 0.1\nA 0 0 0\n",
            "bad.xyz",
            4,
            "columns",
        ),
    ];
    for (text, name, line, needle) in cases {
        let (l, m) = data_error(text, name, Some(&h));
        assert_eq!(l, line, "{name}: {m}");
        assert!(m.contains(needle), "{name}: {m}");
    }
}

/// Thousands of copies of one particle (a broken export) are refused at once,
/// naming the first line, instead of listing n² contacts; the overlapping beads
/// of a dense rod (one body) are not crowding.
#[test]
fn crowded_files_are_refused_but_dense_rods_are_not() {
    let h = BoxHint {
        size: vec![10.0, 10.0, 10.0],
        periodic: false,
    };
    let mut text = String::from("x y z r\n1 1 1 1\n");
    text.push_str(&"5 5 5 1\n".repeat(3000));
    let (line, m) = data_error(&text, "dup.txt", Some(&h));
    assert_eq!(line, 3, "{m}");
    assert!(
        m.contains("3000 particles") && m.contains("not a packed bed"),
        "{m}"
    );
    // 2D too, with a real bed around the copies.
    let h2 = BoxHint {
        size: vec![100.0, 100.0],
        periodic: false,
    };
    let mut text: String = (0..40).map(|k| format!("{} 1 1\n", 1 + 2 * k)).collect();
    text.push_str(&"50 50 1\n".repeat(2000));
    let (line, m) = data_error(&text, "dup2.txt", Some(&h2));
    assert_eq!(line, 41, "{m}");
    // A dense rod of one body: 2000 beads at spacing 0.05 r (each overlaps 39
    // of its own on each side) is a rod; at spacing 0.0001 r (every bead in
    // one cell, each overlapping thousands of its own) it is refused, as a
    // config asking for it is (issue 30: it exhausted the memory).
    let dir = tempfile::tempdir().unwrap();
    let rod = |spacing: f64| {
        let mut csv = String::from("id,species,body,x,y,z,r\n");
        for k in 0..2000 {
            csv.push_str(&format!("{k},0,0,{},5,5,1\n", 1.0 + spacing * k as f64));
        }
        let path = dir.path().join(format!("rod-{spacing}.csv"));
        std::fs::write(&path, csv).unwrap();
        path
    };
    let h_rod = BoxHint {
        size: vec![120.0, 10.0, 10.0],
        periodic: false,
    };
    match read_bed(&rod(0.05), Some(&h_rod)).unwrap() {
        AnyBed::D3(b) => assert_eq!(b.len(), 2000),
        AnyBed::D2(_) => panic!("3D expected"),
    }
    let e = read_bed(&rod(0.0001), Some(&h_rod))
        .unwrap_err()
        .to_string();
    assert!(e.contains("2000 beads of body 0"), "{e}");
}

// ---------------------------------------------------------------------------
// Pictures of a fragmentation (forces, breakage) and the force colouring
// ---------------------------------------------------------------------------

/// Panics unless `text` is well-formed XML: one root element, every tag
/// closed in order, attributes quoted and unique, `<` never in text or
/// values, `&` only in entities.
fn assert_well_formed_xml(text: &str) {
    fn entities_ok(s: &str) -> bool {
        let mut rest = s;
        while let Some(k) = rest.find('&') {
            let tail = &rest[k + 1..];
            let Some(end) = tail.find(';') else {
                return false;
            };
            let name = &tail[..end];
            let ok = matches!(name, "amp" | "lt" | "gt" | "quot" | "apos")
                || name
                    .strip_prefix('#')
                    .is_some_and(|n| !n.is_empty() && n.chars().all(|c| c.is_ascii_digit()));
            if !ok {
                return false;
            }
            rest = &tail[end + 1..];
        }
        true
    }
    let name_end = |s: &str| {
        s.find(|c: char| !(c.is_alphanumeric() || "-_:.".contains(c)))
            .unwrap_or(s.len())
    };
    let mut s = text.trim_start();
    if s.starts_with("<?xml") {
        s = &s[s.find("?>").expect("prolog closed") + 2..];
    }
    let mut stack: Vec<&str> = Vec::new();
    let mut roots = 0;
    loop {
        let lt = s.find('<');
        let chunk = &s[..lt.unwrap_or(s.len())];
        assert!(entities_ok(chunk), "text {chunk:?}");
        if stack.is_empty() {
            assert!(chunk.trim().is_empty(), "text outside the root: {chunk:?}");
        }
        let Some(lt) = lt else { break };
        s = &s[lt + 1..];
        if let Some(rest) = s.strip_prefix('/') {
            let n = name_end(rest);
            let open = stack.pop().expect("a closing tag without its opening");
            assert_eq!(open, &rest[..n], "tags closed out of order");
            let gt = rest.find('>').unwrap();
            assert!(rest[n..gt].trim().is_empty());
            s = &rest[gt + 1..];
            continue;
        }
        let n = name_end(s);
        assert!(n > 0, "a tag without a name: {:?}", &s[..s.len().min(40)]);
        let name = &s[..n];
        if stack.is_empty() {
            roots += 1;
        }
        s = &s[n..];
        let mut seen = Vec::new();
        loop {
            s = s.trim_start();
            if let Some(rest) = s.strip_prefix("/>") {
                s = rest;
                break;
            }
            if let Some(rest) = s.strip_prefix('>') {
                s = rest;
                stack.push(name);
                break;
            }
            let a = name_end(s);
            assert!(
                a > 0,
                "bad attribute in <{name}: {:?}",
                &s[..s.len().min(40)]
            );
            let attr = &s[..a];
            assert!(!seen.contains(&attr), "<{name}> repeats {attr}");
            seen.push(attr);
            let rest = s[a..].trim_start().strip_prefix('=').expect("attribute =");
            let rest = rest.trim_start();
            let q = rest.chars().next().unwrap();
            assert!(q == '"' || q == '\'', "unquoted {attr}");
            let end = rest[1..].find(q).expect("value closed");
            let value = &rest[1..1 + end];
            assert!(
                !value.contains('<') && entities_ok(value),
                "{attr}={value:?}"
            );
            s = &rest[end + 2..];
        }
    }
    assert!(stack.is_empty(), "unclosed {stack:?}");
    assert_eq!(roots, 1);
}

#[test]
fn the_xml_checker_refuses_broken_documents() {
    assert_well_formed_xml("<?xml version=\"1.0\"?>\n<a x=\"1\"><b/><c>t &amp; u</c></a>\n");
    for bad in [
        "<a><b></a></b>",
        "<a x=\"1\" x=\"2\"/>",
        "<a x=1/>",
        "<a>x & y</a>",
        "<a/><b/>",
        "<a>",
    ] {
        assert!(
            std::panic::catch_unwind(|| assert_well_formed_xml(bad)).is_err(),
            "{bad}"
        );
    }
}

/// Checks the four pictures of `frag`: names, PNG sizes, SVG well-formed with
/// one line per bond and one numbered label per break, no NaN or infinity.
fn check_fragmentation_pictures<const D: usize>(
    bed: &Bed<D>,
    frag: &packbed::Fragmentation<D>,
    what: &str,
) -> Vec<(String, Vec<u8>)> {
    let pics = render::fragmentation_pictures(bed, frag).unwrap();
    let names: Vec<&str> = pics.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        ["forces.png", "forces.svg", "breakage.png", "breakage.svg"],
        "{what}"
    );
    for (name, bytes) in &pics {
        if name.ends_with(".png") {
            let p = Pixmap::decode_png(bytes).unwrap();
            assert_eq!(
                (p.width(), p.height()),
                (render::FRAGMENTATION_WIDTH, render::FRAGMENTATION_HEIGHT),
                "{what} {name}"
            );
            // Not blank: the bonds and the legend darken some pixels.
            let dark = p
                .pixels()
                .iter()
                .filter(|c| c.red() < 128 || c.blue() < 128)
                .count();
            assert!(dark > 1000, "{what} {name}: {dark} dark pixels");
            continue;
        }
        let svg = std::str::from_utf8(bytes).unwrap();
        assert_well_formed_xml(svg);
        for bad in ["NaN", "inf"] {
            assert!(!svg.contains(bad), "{what} {name} contains {bad}");
        }
        let lines = svg.matches("<polyline class=\"bond ").count();
        assert_eq!(lines, frag.bonds.len(), "{what} {name}: one line per bond");
        assert_eq!(
            svg.matches("<circle class=\"particle\"").count(),
            bed.len(),
            "{what} {name}"
        );
        if name == "forces.svg" {
            let tension = svg.matches("class=\"bond tension\"").count();
            let expected = (0..frag.bonds.len())
                .filter(|&k| frag.normal(k) > 0.0)
                .count();
            assert_eq!(tension, expected, "{what}");
            assert_eq!(
                svg.matches("class=\"load\"").count(),
                frag.loads.iter().filter(|l| l.force.norm() > 0.0).count(),
                "{what}: one arrow per load"
            );
        } else {
            let n = frag.steps.len();
            assert!(n > 0, "{what}: nothing broke");
            assert_eq!(svg.matches("class=\"bond broken\"").count(), n, "{what}");
            // Only the first breaks are numbered; more would pile up.
            let numbered = n.min(render::NUMBERED_BREAKS);
            assert_eq!(
                svg.matches("class=\"break-label\"").count(),
                numbered,
                "{what}"
            );
            for k in 1..=n {
                assert_eq!(
                    svg.matches(&format!(">{k}</text>")).count(),
                    // The legend's badge shows a 1 as well.
                    usize::from(k <= numbered) + usize::from(k == 1),
                    "{what}: label {k}"
                );
            }
            assert!(!svg.contains(&format!(">{}</text>", n + 1)), "{what}");
        }
    }
    pics
}

fn deposited<const D: usize>(periodic: bool, count: u64) -> Bed<D> {
    let text = format!(
        "dim = {D}\nseed = 7\n\n[box]\ndiameters = 8\nperiodic = {periodic}\n\n\
         [fill]\ncount = {count}\n\n[[species]]\nradius = 10\nratio = 1\n\n\
         [[species]]\nradius = 6\nratio = 1\n"
    );
    crate::common::run::<D>(&crate::common::config(&text)).0
}

#[test]
fn fragmentation_pictures_2d_draw_every_bond_and_number_every_break() {
    use packbed::{fragment, FragmentationConfig};
    for periodic in [false, true] {
        let bed = deposited::<2>(periodic, 120);
        let contacts = packbed::find_contacts(&bed, 1e-6);
        let frag = fragment(&bed, &contacts, &FragmentationConfig::default()).unwrap();
        let what = format!("2D periodic {periodic}");
        let pics = check_fragmentation_pictures(&bed, &frag, &what);
        if periodic {
            // Bonds across the periodic sides are drawn in two halves.
            let svg = std::str::from_utf8(&pics[1].1).unwrap();
            assert!(svg.contains("class=\"bond-image\""), "{what}");
        }
        if std::env::var_os("PACKBED_KEEP_PICTURES").is_some() {
            let d = scratch(&format!("frag2-{periodic}"));
            for (n, b) in &pics {
                std::fs::write(d.join(n), b).unwrap();
            }
            eprintln!("pictures in {}", d.display());
        }
    }
}

#[test]
fn fragmentation_pictures_3d_are_a_projection_with_numbered_breaks() {
    use packbed::{fragment, Breaks, FragmentationConfig};
    let bed = deposited::<3>(false, 150);
    let contacts = packbed::find_contacts(&bed, 1e-6);
    let options = FragmentationConfig {
        breaks: Breaks::Count(12),
        ..FragmentationConfig::default()
    };
    let frag = fragment(&bed, &contacts, &options).unwrap();
    let pics = check_fragmentation_pictures(&bed, &frag, "3D");
    let svg = std::str::from_utf8(&pics[1].1).unwrap();
    assert!(svg.contains("x–z projection"));
    if std::env::var_os("PACKBED_KEEP_PICTURES").is_some() {
        let d = scratch("frag3");
        for (n, b) in &pics {
            std::fs::write(d.join(n), b).unwrap();
        }
        eprintln!("pictures in {}", d.display());
    }
}

#[test]
fn many_breaks_are_coloured_by_order_and_only_the_first_numbered() {
    use packbed::{fragment, Breaks, FragmentationConfig};
    let bed = deposited::<3>(false, 150);
    let contacts = packbed::find_contacts(&bed, 1e-6);
    let options = FragmentationConfig {
        breaks: Breaks::Count(60),
        ..FragmentationConfig::default()
    };
    let frag = fragment(&bed, &contacts, &options).unwrap();
    assert_eq!(frag.steps.len(), 60);
    let pics = check_fragmentation_pictures(&bed, &frag, "3D, 60 breaks");
    let svg = std::str::from_utf8(&pics[3].1).unwrap();
    assert_eq!(svg.matches("class=\"break-label\"").count(), 20);
    assert!(svg.contains("first 20 numbered"));
    // A colour scale from the first break to the last in the legend.
    assert!(svg.contains(">break 1</text>") && svg.contains(">break 60</text>"));
    // The broken bonds take more than one colour: their order shows.
    let colours: std::collections::BTreeSet<&str> = svg
        .split("class=\"bond broken\"")
        .skip(1)
        .filter_map(|rest| {
            let start = rest.find("stroke=\"")? + 8;
            rest.get(start..start + 7)
        })
        .collect();
    assert!(colours.len() > 10, "{colours:?}");
    if std::env::var_os("PACKBED_KEEP_PICTURES").is_some() {
        let d = scratch("frag3-many");
        for (n, b) in &pics {
            std::fs::write(d.join(n), b).unwrap();
        }
        eprintln!("pictures in {}", d.display());
    }
}

#[test]
fn fragmentation_pictures_refuse_another_beds_fragmentation() {
    use packbed::{fragment, FragmentationConfig};
    let bed = bed2();
    let contacts = packbed::find_contacts(&bed, 1e-6);
    let frag = fragment(&bed, &contacts, &FragmentationConfig::default()).unwrap();
    let mut other = bed.clone();
    other.push(Vector([100.0, 120.0]), 5.0, 1);
    let e = render::fragmentation_pictures(&other, &frag).unwrap_err();
    assert!(e.to_string().contains("not of this bed"), "{e}");
}

#[test]
fn force_colours_follow_the_bond_forces_under_shear() {
    use packbed::{fragment, FragmentationConfig};
    let bed = bed2();
    let contacts = packbed::find_contacts(&bed, 1e-6);
    let pal = render::palette(&bed, &ColorBy::Force, Some(&contacts)).unwrap();
    let frag = fragment(&bed, &contacts, &FragmentationConfig::default()).unwrap();
    let f = render::particle_forces(&bed, &frag);
    let top = f.iter().copied().fold(0.0, f64::max);
    assert!(top > 0.0 && f.iter().all(|v| v.is_finite() && *v >= 0.0));
    for (k, &v) in f.iter().enumerate() {
        assert_eq!(pal.colours[k], render::viridis(v / top), "particle {k}");
        // A body's largest bond is at least any of its bonds.
        for (g, force) in frag.bonds.iter().zip(&frag.forces) {
            if g.bead_i as usize == k || g.bead_j == Some(k as u32) {
                assert!(force.norm() <= v + 1e-12);
            }
        }
    }
    assert!(pal.heading.contains("force") && pal.heading.contains("shear"));
    assert_eq!(pal.legend.len(), 5);
    assert_eq!(pal.legend[0].0, render::viridis(1.0));
    // Both formats draw it.
    let opts = RenderOptions {
        color: ColorBy::Force,
        ..RenderOptions::default()
    };
    let svg = render::render_svg(&AnyBed::D2(bed.clone()), &opts).unwrap();
    assert!(svg.contains("largest bond force"));
    let png = render::render_png(&AnyBed::D3(deposited::<3>(false, 60)), &opts).unwrap();
    assert_eq!(Pixmap::decode_png(&png).unwrap().width(), 1200);
}

#[test]
fn fragment_pictures_that_cannot_be_drawn_leave_the_tables_and_a_warning() {
    let dir = scratch("frag-warn");
    let file = dir.join("b.csv");
    std::fs::write(
        &file,
        "x,y,r\n10,10,10\n30,10,10\n50,10,10\n20,27.3205080757,10\n",
    )
    .unwrap();
    let hint = BoxHint {
        size: vec![100.0, 100.0],
        periodic: false,
    };
    let options = packbed::FragmentationConfig {
        load: packbed::Load::Gravity,
        breaks: packbed::Breaks::Count(1),
        kt_over_kn: 1.0,
    };
    let mut done = packbed::fragment_file(&file, Some(&hint), &options, 1e-6).unwrap();
    // A particle the breakage never saw: the pictures refuse to draw it.
    if let AnyBed::D2(b) = &mut done.bed {
        b.push_bead(Vector([90.0, 90.0]), 5.0, 0, 9);
    }
    let out = dir.join("out");
    let written = done.write(&out, true).unwrap();
    assert_eq!(written.warnings.len(), 1, "{:?}", written.warnings);
    assert!(
        written.warnings[0].starts_with("pictures forces.png|svg and breakage.png|svg not written")
    );
    assert!(out.join("bonds.csv").is_file() && out.join("breakage.csv").is_file());
    assert!(!out.join("forces.png").exists());
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(summary.contains("\"warnings\""), "{summary}");
    std::fs::remove_dir_all(&dir).unwrap();
}
