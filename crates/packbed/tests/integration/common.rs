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
