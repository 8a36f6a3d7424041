//! One sparse symmetric positive definite solve with a scalar unknown per node
//! of a graph (the pressures of a pore network): the same elimination order
//! and supernodal factorisation as the stiffness matrix of `packbed fragment`,
//! then one step of iterative refinement.

use super::factor::Factor;
use super::ordering::elimination_order;
use crate::math::{Real, Vector};
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMat, SymbolicSparseColMat};
use faer::{Par, Side};
use rayon::prelude::*;

/// Dense blocks split a fixed number of ways, so that the sums (and the
/// answer's last bits) do not depend on the number of threads.
const DENSE_DEGREE: usize = 8;

/// Above this many unknowns the system is solved by conjugate gradients with
/// a multigrid preconditioner (the direct factor's cost grows as n² in 3D);
/// below, the direct factor is faster.
pub const DIRECT_LIMIT: usize = 30_000;

/// Above this many unknowns a failed iterative solve is not retried with the
/// direct factor (6·10^5 unknowns took 2.6 GB and 14 s per factor).
const DIRECT_FALLBACK: usize = 300_000;

/// Relative residual the iterative solve reaches. The flow deflates its flux
/// balances, so they hold far below the tolerance (they set 1e-11 before the
/// deflation: 4e-10 at 1e-10 on the sieve examples); but not at any
/// tolerance: at 1e-6 a periodic axis' balance reached 5.8e-10 on a
/// `sieve-sweep` bed, too near the 1e-9 a reported `k` must meet; at 1e-7 the largest found is
/// 1.7e-11. `k` to seven digits is far finer than the spread of replicate
/// beds or the network model's ±25 % against Stokes flow. Against a solve to
/// 1e-11, at 1e-7 `k_z` moved by 1.7e-8 (10^5 equal spheres), 1.3e-7
/// (`cake-gsd1.6`), 1.6e-8 (`sieve-b`), 1.2e-8 (`cake-gsd1.2`), and at 10^6
/// spheres by 1.2e-8 from its value at 1e-8; `k_x` and `k_y` by 1.1e-11 at
/// most. A tolerance of 1e-8 would take a fifth more steps (43 against 36
/// at 10^6 spheres) for digits no one can use.
const TOLERANCE: Real = 1e-7;

/// The iterative solve, `None` if the hierarchy cannot be built or CG stalls
/// (the direct solve then decides). Right-hand side `k`'s matrix is `A +
/// diag(shifts[k])` (an empty shift: none); one hierarchy serves them all
/// and one sweep carries them side by side (at most three): the matrix is
/// read once per step, not once per right-hand side, and the rows' chains of
/// dependent operations run side by side.
///
/// The unknowns are renumbered along a Hilbert curve of `points` first: a
/// network's own numbering scatters neighbours across memory (median index
/// gap 878 at 6·10^6 pores), and every sweep of the multigrid then waits on
/// the cache.
fn iterative<const D: usize>(systems: Systems<D>, tol: Real) -> Option<Vec<Vec<Real>>> {
    let Systems {
        points,
        diag,
        off,
        shifts,
        rhs,
        deflate,
    } = systems;
    // Each input goes as soon as it has served: at 10^6 spheres the points,
    // the couplings and the right-hand sides are 0.6 GB beside the hierarchy.
    let coords: Vec<[Real; D]> = points.into_par_iter().map(|p| p.0).collect();
    let order = crate::math::hilbert::order(&coords);
    drop(coords);
    let mut new_of = vec![0u32; order.len()];
    for (new, &old) in order.iter().enumerate() {
        new_of[old as usize] = new as u32;
    }
    let csr = super::amg::Csr::renumbered(&diag, off, &new_of)?;
    drop(diag);
    let renumber =
        |b: Vec<Real>| -> Vec<Real> { order.par_iter().map(|&o| b[o as usize]).collect() };
    // One system when every right-hand side has the same shift.
    let same = shifts.windows(2).all(|w| w[0] == w[1]);
    let systems: Vec<Vec<Real>> = if same {
        shifts
            .into_iter()
            .take(1)
            .filter(|s| !s.is_empty())
            .map(renumber)
            .collect()
    } else {
        let n = order.len();
        shifts
            .into_iter()
            .map(|s| renumber(if s.is_empty() { vec![0.0; n] } else { s }))
            .collect()
    };
    let mg = super::amg::Multigrid::shifted(csr, systems)?;
    let rhs: Vec<Vec<Real>> = rhs.into_iter().map(renumber).collect();
    let deflate = deflate.map(|w| w.into_iter().map(renumber).collect::<Vec<_>>());
    let x = match rhs.len() {
        1 => solve_k::<1>(mg, rhs, deflate, tol)?,
        2 => solve_k::<2>(mg, rhs, deflate, tol)?,
        3 => solve_k::<3>(mg, rhs, deflate, tol)?,
        _ if same => {
            // Otherwise each on its own thread: the hierarchy is shared and
            // read-only, and every solve runs in a fixed order whatever the
            // threads.
            let mut w = deflate.map(|w| w.into_iter().map(|w| [w]).collect::<Vec<_>>());
            let solved: Option<Vec<Vec<Real>>> = rhs
                .into_par_iter()
                .enumerate()
                .map(|(k, b)| {
                    let w = w.as_ref().map(|w| w[k].clone());
                    let ([x], _) = mg.solve_deflated([b], w, tol, 1000)?;
                    Some(x)
                })
                .collect();
            w.take();
            solved?
        }
        _ => return None,
    };
    Some(
        x.iter()
            .map(|x| new_of.par_iter().map(|&n| x[n as usize]).collect())
            .collect(),
    )
}

/// `K` right-hand sides through one hierarchy; the hierarchy goes before the
/// answer is unpacked (at 10^6 spheres it was the flow's peak).
fn solve_k<const K: usize>(
    mg: super::amg::Multigrid,
    rhs: Vec<Vec<Real>>,
    deflate: Option<Vec<Vec<Real>>>,
    tol: Real,
) -> Option<Vec<Vec<Real>>> {
    let b: [Vec<Real>; K] = rhs.try_into().ok()?;
    let w = match deflate {
        Some(w) => Some(<[Vec<Real>; K]>::try_from(w).ok()?),
        None => None,
    };
    let (x, _) = mg.solve_deflated(b, w, tol, 1000)?;
    drop(mg);
    Some(x.into())
}

/// Why a system could not be solved.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpdError {
    /// The matrix is not positive definite (a node with no path to a fixed one).
    NotPositive,
    /// The symbolic analysis failed (too large for its indices).
    Analysis,
    /// The iterative solve did not converge and the system is too large to
    /// factor.
    NotConverged,
}

/// Solves `A x = b` for each right-hand side of `rhs`, where `A` has the
/// diagonal `diag` and the symmetric off-diagonal entries `off` (`(i, j, a_ij)`
/// with `i != j`, each pair once or several times, summed). `points` places
/// the nodes for the 2D order.
#[cfg(test)]
pub fn solve_spd<const D: usize>(
    points: &[Vector<D>],
    diag: &[Real],
    off: &[(u32, u32, Real)],
    rhs: &[Vec<Real>],
) -> Result<Vec<Vec<Real>>, SpdError> {
    solve_spd_shifted(Systems {
        points: points.to_vec(),
        diag: diag.to_vec(),
        off: off.to_vec(),
        shifts: vec![Vec::new(); rhs.len()],
        rhs: rhs.to_vec(),
        deflate: None,
    })
}

/// Sparse symmetric systems that share their couplings and differ in their
/// diagonals: right-hand side `k`'s matrix has the diagonal `diag +
/// shifts[k]` (an empty shift: `diag`) and the symmetric off-diagonal
/// entries `off` (`(i, j, a_ij)`, `i != j`, repeated pairs summed).
/// `points` places the nodes. If the systems are solved iteratively, the
/// residual of right-hand side `k` stays orthogonal to `deflate[k]` to
/// rounding whatever the tolerance (a conserved total, such as the net flux
/// through a slab, then holds exactly; see
/// [`super::amg::Multigrid::solve_deflated`]); the direct solve meets it to
/// rounding anyway. The inputs are taken, so that a large system's are freed
/// once the hierarchy holds them.
#[derive(Clone, Debug)]
pub struct Systems<const D: usize> {
    /// The position of each node (unknown).
    pub points: Vec<Vector<D>>,
    /// The diagonal the systems share.
    pub diag: Vec<Real>,
    /// The off-diagonal entries `(i, j, a_ij)`, `i != j`, repeated pairs summed.
    pub off: Vec<(u32, u32, Real)>,
    /// Per right-hand side, the shift added to `diag` (empty: none).
    pub shifts: Vec<Vec<Real>>,
    /// The right-hand sides, one per system.
    pub rhs: Vec<Vec<Real>>,
    /// Per right-hand side, the vector its residual stays orthogonal to
    /// when solved iteratively (`None`: no such vector).
    pub deflate: Option<Vec<Vec<Real>>>,
}

/// Solves [`Systems`] that differ in their diagonals. Solved iteratively,
/// one hierarchy serves them all (at most three that differ); directly, each
/// distinct shift is factored.
pub fn solve_spd_shifted<const D: usize>(systems: Systems<D>) -> Result<Vec<Vec<Real>>, SpdError> {
    let n = systems.diag.len();
    let k = systems.rhs.len();
    assert_eq!(systems.shifts.len(), k, "one shift per right-hand side");
    if let Some(w) = &systems.deflate {
        assert_eq!(w.len(), k, "one deflation vector per right-hand side");
    }
    if n == 0 {
        return Ok(vec![Vec::new(); k]);
    }
    if n > DIRECT_FALLBACK {
        // The direct factor of a large 3D network does not fit in memory
        // (4.7·10^10 bytes at 6·10^6 pores): refuse rather than abort.
        return iterative(systems, TOLERANCE).ok_or(SpdError::NotConverged);
    }
    if n > DIRECT_LIMIT {
        if let Some(x) = iterative(systems.clone(), TOLERANCE) {
            return Ok(x);
        }
    }
    let Systems {
        points,
        diag,
        off,
        shifts,
        rhs,
        ..
    } = systems;
    // One factor per distinct shift, its right-hand sides together.
    let mut x: Vec<Vec<Real>> = vec![Vec::new(); rhs.len()];
    let mut done = vec![false; rhs.len()];
    for k in 0..rhs.len() {
        if done[k] {
            continue;
        }
        let group: Vec<usize> = (k..rhs.len())
            .filter(|&j| !done[j] && shifts[j] == shifts[k])
            .collect();
        let shifted: Vec<Real>;
        let d = if shifts[k].is_empty() {
            &diag
        } else {
            shifted = diag.iter().zip(&shifts[k]).map(|(d, s)| d + s).collect();
            &shifted
        };
        let b: Vec<Vec<Real>> = group.iter().map(|&j| rhs[j].clone()).collect();
        for (&j, xj) in group.iter().zip(direct(&points, d, &off, &b)?) {
            x[j] = xj;
            done[j] = true;
        }
    }
    Ok(x)
}

/// The direct solve: the fragment solver's order and supernodal factor.
fn direct<const D: usize>(
    points: &[Vector<D>],
    diag: &[Real],
    off: &[(u32, u32, Real)],
    rhs: &[Vec<Real>],
) -> Result<Vec<Vec<Real>>, SpdError> {
    let n = diag.len();
    // The graph in compressed rows, both directions.
    let mut offsets = vec![0usize; n + 1];
    for &(i, j, _) in off {
        offsets[i as usize + 1] += 1;
        offsets[j as usize + 1] += 1;
    }
    for k in 0..n {
        offsets[k + 1] += offsets[k];
    }
    let mut fill = offsets.clone();
    let mut neighbours = vec![0u32; offsets[n]];
    let mut values = vec![0.0; offsets[n]];
    for &(i, j, a) in off {
        for (from, to) in [(i, j), (j, i)] {
            let f = &mut fill[from as usize];
            neighbours[*f] = to;
            values[*f] = a;
            *f += 1;
        }
    }
    let order = elimination_order(points, &offsets, &neighbours);
    let fwd: Vec<usize> = order.iter().map(|&v| v as usize).collect();
    let mut inv = vec![0usize; n];
    for (new, &old) in fwd.iter().enumerate() {
        inv[old] = new;
    }
    // Lower triangle in the original order: column j holds j and the higher
    // neighbours, repeated entries summed.
    let mut col_ptr = Vec::with_capacity(n + 1);
    let mut row_idx = Vec::with_capacity(n + offsets[n] / 2);
    let mut val = Vec::with_capacity(n + offsets[n] / 2);
    col_ptr.push(0usize);
    let mut column: Vec<(u32, Real)> = Vec::new();
    for j in 0..n {
        column.clear();
        column.extend(
            (offsets[j]..offsets[j + 1])
                .filter(|&k| neighbours[k] as usize > j)
                .map(|k| (neighbours[k], values[k])),
        );
        column.sort_by_key(|e| e.0);
        row_idx.push(j);
        val.push(diag[j]);
        for &(i, a) in &column {
            if *row_idx.last().expect("the diagonal is there") == i as usize {
                *val.last_mut().expect("the diagonal is there") += a;
            } else {
                row_idx.push(i as usize);
                val.push(a);
            }
        }
        col_ptr.push(row_idx.len());
    }
    let pattern = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
    let ordering = SymmetricOrdering::Custom(PermRef::new_checked(&fwd, &inv, n));
    let params = CholeskySymbolicParams {
        supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
        ..Default::default()
    };
    let symbolic = factorize_symbolic_cholesky(pattern.as_ref(), Side::Lower, ordering, params)
        .map_err(|_| SpdError::Analysis)?;
    let mut factor = Factor::new(symbolic, Par::rayon(DENSE_DEGREE)).ok_or(SpdError::Analysis)?;
    let matrix = SparseColMat::new(pattern, val);
    factor
        .factorize(matrix.as_ref())
        .map_err(|_| SpdError::NotPositive)?;
    let apply = |x: &[Real]| -> Vec<Real> {
        let mut y: Vec<Real> = diag.iter().zip(x).map(|(d, x)| d * x).collect();
        for (i, yi) in y.iter_mut().enumerate() {
            for k in offsets[i]..offsets[i + 1] {
                *yi += values[k] * x[neighbours[k] as usize];
            }
        }
        y
    };
    Ok(rhs
        .iter()
        .map(|b| {
            let mut x = factor.backward(factor.forward(b));
            // One refinement step: the residual of the rounded factor, solved again.
            let ax = apply(&x);
            let r: Vec<Real> = b.iter().zip(&ax).map(|(b, a)| b - a).collect();
            let dx = factor.backward(factor.forward(&r));
            for (x, d) in x.iter_mut().zip(dx) {
                *x += d;
            }
            x
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// A path graph with both ends tied to ground: the discrete Laplacian with
    /// a known solution.
    #[test]
    fn a_chain_of_conductances_has_a_linear_pressure() {
        // Nodes 0..n between fixed pressures 1 (left) and 0 (right), unit links.
        let n = 50;
        let points: Vec<Vector<2>> = (0..n).map(|i| Vector([i as Real, 0.0])).collect();
        let diag = vec![2.0; n];
        let off: Vec<(u32, u32, Real)> =
            (0..n - 1).map(|i| (i as u32, i as u32 + 1, -1.0)).collect();
        let mut b = vec![0.0; n];
        b[0] = 1.0;
        let x = solve_spd(&points, &diag, &off, &[b]).unwrap();
        for (i, xi) in x[0].iter().enumerate() {
            let exact = 1.0 - (i + 1) as Real / (n + 1) as Real;
            assert!((xi - exact).abs() < 1e-13, "{i}: {xi} {exact}");
        }
    }

    /// The shared iterative solve of three systems that differ in their
    /// diagonals against the direct factor of each.
    #[test]
    fn shifted_systems_solved_together_match_each_factored() {
        let m = 32;
        let n = m * m * m;
        assert!(n > DIRECT_LIMIT);
        let id = |i: usize, j: usize, k: usize| (i + m * (j + m * k)) as u32;
        let mut off = Vec::new();
        let mut points = Vec::new();
        for k in 0..m {
            for j in 0..m {
                for i in 0..m {
                    points.push(Vector([i as Real, j as Real, k as Real]));
                    let g = 1.0 + ((i * 5 + j * 3 + k) % 7) as Real;
                    if i + 1 < m {
                        off.push((id(i, j, k), id(i + 1, j, k), -g));
                    }
                    if j + 1 < m {
                        off.push((id(i, j, k), id(i, j + 1, k), -2.0 * g));
                    }
                    if k + 1 < m {
                        off.push((id(i, j, k), id(i, j, k + 1), -0.5 * g));
                    }
                }
            }
        }
        let mut diag = vec![0.0; n];
        for &(i, j, a) in &off {
            diag[i as usize] -= a;
            diag[j as usize] -= a;
        }
        let layer = m * m;
        let mut shifts = vec![vec![0.0; n]; 3];
        shifts[0][..layer].fill(3.0);
        shifts[0][n - layer..].fill(3.0);
        shifts[1][0] = diag[0];
        shifts[2] = shifts[1].clone();
        let rhs: Vec<Vec<Real>> = (0..3)
            .map(|s| {
                let v: Vec<Real> = (0..n)
                    .map(|i| (((i * (3 + s)) % 17) as Real).sin())
                    .collect();
                let mean = v.iter().sum::<Real>() / n as Real;
                v.iter()
                    .map(|x| x - if s > 0 { mean } else { 0.0 })
                    .collect()
            })
            .collect();
        let together = iterative(
            Systems {
                points: points.clone(),
                diag: diag.clone(),
                off: off.clone(),
                shifts: shifts.clone(),
                rhs: rhs.clone(),
                deflate: None,
            },
            1e-11,
        )
        .unwrap();
        for k in 0..3 {
            let d: Vec<Real> = diag.iter().zip(&shifts[k]).map(|(d, s)| d + s).collect();
            let alone = direct(&points, &d, &off, std::slice::from_ref(&rhs[k])).unwrap();
            let scale = alone[0].iter().fold(0.0, |a: Real, v| a.max(v.abs()));
            for (u, v) in together[k].iter().zip(&alone[0]) {
                assert!((u - v).abs() < 1e-6 * scale, "system {k}: {u} {v}");
            }
        }
    }

    #[test]
    fn a_floating_node_is_not_positive() {
        let points = vec![Vector([0.0, 0.0, 0.0]), Vector([1.0, 0.0, 0.0])];
        let r = solve_spd(&points, &[1.0, 1.0], &[(0, 1, -1.0)], &[vec![1.0, 0.0]]);
        assert_eq!(r, Err(SpdError::NotPositive));
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(48))]
        /// Random weighted graphs, diagonally dominant: the residual is tiny.
        #[test]
        fn random_laplacians_are_solved(
            edges in prop::collection::vec((0u32..60, 0u32..60, 0.01f64..10.0), 1..300),
            ground in prop::collection::vec(0.001f64..1.0, 60),
        ) {
            let n = 60;
            let points: Vec<Vector<3>> = (0..n)
                .map(|i| Vector([(i % 4) as Real, (i / 4 % 4) as Real, (i / 16) as Real]))
                .collect();
            let off: Vec<(u32, u32, Real)> = edges
                .iter()
                .filter(|e| e.0 != e.1)
                .map(|&(i, j, g)| (i, j, -g))
                .collect();
            let mut diag = ground.clone();
            for &(i, j, a) in &off {
                diag[i as usize] -= a;
                diag[j as usize] -= a;
            }
            let b: Vec<Real> = (0..n).map(|i| (i as Real).sin()).collect();
            let x = solve_spd(&points, &diag, &off, std::slice::from_ref(&b)).unwrap();
            let mut ax: Vec<Real> = diag.iter().zip(&x[0]).map(|(d, x)| d * x).collect();
            for &(i, j, a) in &off {
                ax[i as usize] += a * x[0][j as usize];
                ax[j as usize] += a * x[0][i as usize];
            }
            for i in 0..n {
                prop_assert!((ax[i] - b[i]).abs() < 1e-9, "{} {}", ax[i], b[i]);
            }
        }
    }
}
