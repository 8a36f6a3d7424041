//! Helpers every test module shares: configs from TOML, deposition of a plan,
//! and the checker's verdict.

use packbed::Bed;
use packbed::Config;
use packbed::Real;
use packbed::{check_bed_with, CheckReport as Report, InvariantChecks};
use packbed::{deposit, DepositReport};
use packbed::{run_bed, FiltrationSummary, FinishedBed};

/// Gap tolerance of the model (`docs/reference/model.md`, "Exactness": exact to 1e-9 r).
pub const TOL: Real = 1e-9;

/// A config from TOML text, as a user writes it; panics with the text.
pub fn config(text: &str) -> Config {
    Config::from_toml(text, "test").unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// The bed of `c`, deposited in dimension `D`, and its report.
pub fn run<const D: usize>(c: &Config) -> (Bed<D>, DepositReport) {
    let plan = c.plan::<D>().unwrap_or_else(|e| panic!("plan: {e}"));
    deposit::<D>(&plan, &mut |_| std::ops::ControlFlow::Continue(()))
        .unwrap_or_else(|e| panic!("deposit: {e}"))
}

/// The checker's report on `b` under `checks`; panics naming `what` unless
/// the bed passes, every particle counted.
pub fn assert_checked<const D: usize>(b: &Bed<D>, checks: &InvariantChecks, what: &str) -> Report {
    let rep = check_bed_with(b, checks);
    assert!(rep.is_ok(), "{what}: {rep}");
    assert_eq!(rep.particles, b.len());
    rep
}

/// The finished run of `text`; panics if the run fails or warns that the
/// filtration curve could not be solved.
pub fn filtered_run(text: &str) -> FinishedBed {
    let run = run_bed(&config(text), &mut |_| {}).unwrap_or_else(|e| panic!("{e}"));
    let w = &run.summary.warnings;
    assert!(w.iter().all(|w| !w.starts_with("filtration")), "{w:?}");
    run
}

/// The filtration of the run of `text` ([`filtered_run`]).
pub fn filtered(text: &str) -> FiltrationSummary {
    filtered_run(text).summary.filtration.expect("a filtration")
}

/// Asserts that Ruth's fitted α of `f` is within 5 % of the network's.
pub fn assert_alpha_fits(f: &FiltrationSummary) {
    let (fit, net) = (
        f.alpha_fit_m_per_kg.expect("a fitted α"),
        f.alpha_network_m_per_kg.expect("the network's α"),
    );
    assert!(
        (fit / net - 1.0).abs() < 0.05,
        "α fit {fit:e}, network {net:e}"
    );
}

/// Order parameter `<(3 cos² θ − 1)/2>` of chain axes with respect to the
/// vertical (end bead to end bead; periodic images unwrapped).
pub fn order_parameter<const D: usize>(bed: &Bed<D>) -> (Real, usize) {
    let mut sum = 0.0;
    let mut n = 0;
    let mut i = 0;
    while i < bed.len() {
        let mut j = i;
        while j + 1 < bed.len() && bed.bodies[j + 1] == bed.bodies[i] {
            j += 1;
        }
        if j > i {
            let a = bed.container.displacement(&bed.centres[i], &bed.centres[j]);
            let c = a[D - 1] / a.norm();
            sum += 0.5 * (3.0 * c * c - 1.0);
            n += 1;
        }
        i = j + 1;
    }
    (sum / n.max(1) as Real, n)
}
