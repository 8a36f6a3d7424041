//! The command and the Python package use the library through its front door,
//! the crate root, so that the modules below it can change shape without them.

use std::fs;
use std::path::Path;

/// Namespaces the root re-exports as wholes: families of functions that read
/// best with their module's name (`slurm::submit`, `text::run_text`).
const NAMESPACES: [&str; 5] = ["bench", "compare", "render", "slurm", "text"];

/// Every `packbed::module::` path in the Rust files under `dir`, as
/// `file:line: path`, whose module is not a root namespace.
fn reaching_past(dir: &Path, found: &mut Vec<String>) {
    for entry in fs::read_dir(dir).unwrap().flatten() {
        let path = entry.path();
        if path.is_dir() {
            reaching_past(&path, found);
            continue;
        }
        if path.extension().is_none_or(|e| e != "rs") {
            continue;
        }
        let text = fs::read_to_string(&path).unwrap();
        for (i, line) in text.lines().enumerate() {
            let mut rest = line;
            while let Some(at) = rest.find("packbed::") {
                rest = &rest[at + "packbed::".len()..];
                let name: String = rest
                    .chars()
                    .take_while(|c| c.is_ascii_lowercase() || *c == '_')
                    .collect();
                let is_module = !name.is_empty() && rest[name.len()..].starts_with("::");
                if is_module && !NAMESPACES.contains(&name.as_str()) {
                    found.push(format!("{}:{}: packbed::{name}::", path.display(), i + 1));
                }
            }
        }
    }
}

#[test]
fn the_command_and_python_use_only_the_front_door() {
    let crates = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut found = Vec::new();
    for dir in ["packbed-cli/src", "packbed-py/src"] {
        reaching_past(&crates.join(dir), &mut found);
    }
    assert!(
        found.is_empty(),
        "reaching past the root:\n{}",
        found.join("\n")
    );
}

#[test]
fn a_path_past_the_root_is_found() {
    let dir = std::env::temp_dir().join(format!("packbed-front-door-{}", std::process::id()));
    fs::create_dir_all(&dir).unwrap();
    fs::write(
        dir.join("a.rs"),
        "use packbed::slurm::submit;\nuse packbed::io::atomic::x;\nlet t = packbed::Config::default();\n",
    )
    .unwrap();
    let mut found = Vec::new();
    reaching_past(&dir, &mut found);
    fs::remove_dir_all(&dir).unwrap();
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(found[0].ends_with("a.rs:2: packbed::io::"), "{found:?}");
}
