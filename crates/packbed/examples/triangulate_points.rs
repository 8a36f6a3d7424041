//! The regular triangulation alone on weighted points, as `scripts/bench-cgal.sh`
//! runs CGAL's: reads lines `x y z w` (w = r²), triangulates them RUNS times
//! and prints each run's seconds and the least. With `--checksum`, also a hash
//! of the input cells (vertices and neighbours, slot order), to show that two
//! builds make the same cells.
//!
//! `cargo run --release -p packbed --example triangulate_points -- POINTS [RUNS] [--checksum]`
//! (RUNS 0 reads the file only, so that a profiler can subtract the reading.)
use packbed::Triangulation;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let checksum = args.iter().any(|a| a == "--checksum");
    let args: Vec<&String> = args.iter().filter(|a| *a != "--checksum").collect();
    let Some(path) = args.first() else {
        eprintln!("usage: triangulate_points POINTS [RUNS] [--checksum]");
        std::process::exit(2);
    };
    let runs: usize = match args.get(1).map(|s| s.parse()) {
        None => 3,
        Some(Ok(n)) => n,
        Some(Err(_)) => {
            eprintln!("RUNS must be a whole number");
            std::process::exit(2);
        }
    };
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| {
        eprintln!("cannot read {path}: {e}");
        std::process::exit(2);
    });
    let (mut points, mut weights) = (Vec::new(), Vec::new());
    for (n, line) in text.lines().enumerate() {
        let v: Result<Vec<f64>, _> = line.split_whitespace().map(str::parse).collect();
        match v.as_deref() {
            Ok([x, y, z, w]) if [x, y, z, w].iter().all(|v| v.is_finite()) => {
                points.push([*x, *y, *z]);
                weights.push(*w);
            }
            _ => {
                eprintln!("{path}:{}: expected four finite numbers `x y z w`", n + 1);
                std::process::exit(2);
            }
        }
    }
    let mut least = f64::INFINITY;
    for _ in 0..runs {
        let t = std::time::Instant::now();
        let tri = Triangulation::<3>::new(&points, &weights);
        let seconds = t.elapsed().as_secs_f64();
        least = least.min(seconds);
        // Two pieces leave no far cells: every slot is an input cell.
        let pieces = if tri.input_cells().count() == tri.slots() {
            2
        } else {
            1
        };
        print!("{seconds:.3} s ({pieces} pieces)  ");
        if checksum {
            let mut h = 0xcbf2_9ce4_8422_2325u64;
            for c in 0..tri.slots() as u32 {
                if tri.is_input_cell(c) {
                    for &x in tri.vertices(c).iter().chain(tri.neighbours(c)) {
                        h = (h ^ u64::from(x)).wrapping_mul(0x100_0000_01b3);
                    }
                }
            }
            print!("(checksum {h:016x}, {} hidden)  ", tri.hidden().len());
        }
    }
    println!("points {} least {least:.3} s", points.len());
}
