//! Integration tests of how `packbed` reads bed files and writes its outputs:
//! refusals of inconsistent input, checks reported on input beds, CSV quoting,
//! temporary files after interruptions, unwritable output directories.

mod common;

use common::{assert_user_error, Scratch};
use serde_json::Value;

fn summary(s: &Scratch, out: &str) -> Value {
    serde_json::from_str(&s.read(&format!("{out}/summary.json"))).unwrap()
}

// ---- counts ---------------------------------------------------------------

/// Body ids of a bed file may be sparse (molecule ids of another tool): the
/// count is of distinct bodies, not the largest id + 1.
#[test]
fn bodies_are_counted_not_numbered() {
    let s = Scratch::new();
    let f = s.input(
        "sparse.csv",
        "x,y,r,body\n1,1,1,0\n3,1,1,88000\n5,1,1,88000\n7,1,1,17\n",
    );
    s.ok(&["analyze", f.to_str().unwrap(), "--box", "8,10", "--out", "a", "-q"]);
    let v = summary(&s, "a");
    assert_eq!(v["counts"]["particles"], 4);
    assert_eq!(v["counts"]["bodies"], 3);
}
