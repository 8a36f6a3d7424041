//! ARCHITECTURE.md is a map, and a map must be true of the code it draws.
//! This test checks what the map states in checkable form:
//!
//! - the front pages stay short: ARCHITECTURE.md at most 400 lines,
//!   README.md 350, BENCHMARKS.md 600;
//! - every table with a `lines` column (and optionally a `files` column)
//!   states the size of the path in its first cell: the lines and files of
//!   source (`.rs`, `.py`, `.pyi`, `.sh`) under it, within 15 % (files: at
//!   least one either way), so that ordinary edits do not break the map but a
//!   room that doubled or vanished does;
//! - the floors table (the table whose first column is `floor`): every
//!   module of the library (`crates/packbed/src/*`) stands on exactly one
//!   floor, and its code (comments and `#[cfg(test)]` modules left out)
//!   names, by `crate::X` paths, only modules on lower floors; `crate::Name`
//!   of a root re-export is an arrow up to `lib.rs`;
//! - every path ARCHITECTURE.md and docs/design/*.md name in backticks
//!   exists in the repository.

use std::fs;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn read(path: &Path) -> String {
    fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The lines of a Markdown text outside fenced blocks, with their 1-based
/// numbers.
fn prose(markdown: &str) -> Vec<(usize, &str)> {
    let mut fenced = false;
    let mut out = Vec::new();
    for (i, line) in markdown.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if !fenced {
            out.push((i + 1, line));
        }
    }
    out
}

/// The inline code spans of a line.
fn code_spans(line: &str) -> Vec<&str> {
    line.split('`').skip(1).step_by(2).collect()
}

/// The cells of a table row (`| a | b |`), trimmed; `None` if the line is
/// not a row.
fn cells(line: &str) -> Option<Vec<&str>> {
    let line = line.trim();
    let inner = line.strip_prefix('|')?.strip_suffix('|')?;
    Some(inner.split('|').map(str::trim).collect())
}

/// The tables of a Markdown text: each a header and its rows (with their
/// line numbers), the separator row dropped.
#[allow(clippy::type_complexity)]
fn tables(markdown: &str) -> Vec<(Vec<String>, Vec<(usize, Vec<String>)>)> {
    let mut out: Vec<(Vec<String>, Vec<(usize, Vec<String>)>)> = Vec::new();
    let mut in_table = false;
    for (n, line) in prose(markdown) {
        let Some(row) = cells(line) else {
            in_table = false;
            continue;
        };
        let row: Vec<String> = row.into_iter().map(String::from).collect();
        if !in_table {
            out.push((row, Vec::new()));
            in_table = true;
        } else if row.iter().all(|c| c.chars().all(|c| c == '-' || c == ':')) {
            continue;
        } else {
            out.last_mut().unwrap().1.push((n, row));
        }
    }
    out
}

/// A number as the map writes it: `24,300`, `~1,200`, `6.2k`.
fn number(cell: &str) -> Option<f64> {
    let t = cell.trim().trim_start_matches('~').replace(',', "");
    if let Some(k) = t.strip_suffix('k') {
        return k.parse::<f64>().ok().map(|v| v * 1000.0);
    }
    t.parse().ok()
}

/// One stated size: the line of the map, the path, its files and lines.
#[derive(Debug)]
struct SizeClaim {
    line: usize,
    path: String,
    files: Option<f64>,
    lines: f64,
}

/// The sizes a Markdown text states: every row of every table that has a
/// `lines` column, the path being the first code span of the row's first cell.
fn size_claims(markdown: &str) -> Vec<SizeClaim> {
    let mut out = Vec::new();
    for (header, rows) in tables(markdown) {
        let Some(lc) = header.iter().position(|h| h == "lines") else {
            continue;
        };
        let fc = header.iter().position(|h| h == "files");
        for (line, row) in rows {
            let path = code_spans(&row[0]).first().map(|s| s.to_string());
            let lines = row.get(lc).and_then(|c| number(c));
            let (Some(path), Some(lines)) = (path, lines) else {
                panic!("ARCHITECTURE.md:{line}: a size row needs a `path` and a number of lines");
            };
            let files = fc.and_then(|c| row.get(c)).and_then(|c| number(c));
            out.push(SizeClaim {
                line,
                path,
                files,
                lines,
            });
        }
    }
    out
}

/// The source files (`.rs`, `.py`, `.pyi`, `.sh`) under `path` (or `path`
/// itself), build output left out.
fn sources(path: &Path, out: &mut Vec<PathBuf>) {
    if path.is_file() {
        if path
            .extension()
            .is_some_and(|e| ["rs", "py", "pyi", "sh"].contains(&e.to_str().unwrap_or("")))
        {
            out.push(path.to_path_buf());
        }
        return;
    }
    let Ok(entries) = fs::read_dir(path) else {
        return;
    };
    for entry in entries.flatten() {
        let p = entry.path();
        if p.file_name().is_some_and(|n| n == "target" || n == ".git") {
            continue;
        }
        sources(&p, out);
    }
}

/// The files and lines of source under a path.
fn measure(path: &Path) -> (usize, usize) {
    let mut files = Vec::new();
    sources(path, &mut files);
    let lines = files
        .iter()
        .map(|f| fs::read_to_string(f).unwrap_or_default().lines().count())
        .sum();
    (files.len(), lines)
}

/// The stated sizes that the tree at `root` does not bear out.
fn wrong_sizes(root: &Path, markdown: &str) -> Vec<String> {
    let mut wrong = Vec::new();
    for claim in size_claims(markdown) {
        let path = root.join(&claim.path);
        if !path.exists() {
            wrong.push(format!(
                "line {}: `{}` does not exist",
                claim.line, claim.path
            ));
            continue;
        }
        let (files, lines) = measure(&path);
        if (lines as f64 - claim.lines).abs() > 0.15 * claim.lines {
            wrong.push(format!(
                "line {}: `{}` has {lines} lines, the map says {}",
                claim.line, claim.path, claim.lines
            ));
        }
        if let Some(stated) = claim.files {
            if (files as f64 - stated).abs() > (0.15 * stated).max(1.0) {
                wrong.push(format!(
                    "line {}: `{}` has {files} files, the map says {stated}",
                    claim.line, claim.path
                ));
            }
        }
    }
    wrong
}

/// The floors table: (floor, rooms) with the rooms as the map names them.
fn floors(markdown: &str) -> Vec<(u32, Vec<String>)> {
    let (_, rows) = tables(markdown)
        .into_iter()
        .find(|(header, _)| header.first().is_some_and(|h| h == "floor"))
        .expect("ARCHITECTURE.md has no floors table (a table whose first column is `floor`)");
    rows.into_iter()
        .map(|(line, row)| {
            let floor = row[0]
                .parse()
                .unwrap_or_else(|_| panic!("ARCHITECTURE.md:{line}: `{}` is not a floor", row[0]));
            let rooms = code_spans(&row[1]).into_iter().map(String::from).collect();
            (floor, rooms)
        })
        .collect()
}

/// The library's module a name of `crates/packbed/src` stands for:
/// `analysis/` and `analysis` are `analysis`, `bed.rs` is `bed`.
fn module_name(name: &str) -> String {
    let name = name.trim_end_matches('/');
    name.strip_suffix(".rs").unwrap_or(name).to_string()
}

/// The modules of the library a source text names by `crate::` paths, with
/// their lines: comments and `#[cfg(test)]` modules left out. A `crate::`
/// path whose first name is not a module (a root re-export) names `lib`.
fn crate_paths(text: &str, modules: &[String]) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    let mut lines = text.lines().enumerate().peekable();
    while let Some((i, line)) = lines.next() {
        let trimmed = line.trim_start();
        if trimmed.starts_with("//") {
            continue;
        }
        if trimmed.starts_with("#[cfg(test)]") {
            let next = lines.peek().map(|(_, l)| l.trim_start()).unwrap_or("");
            if next.starts_with("mod ") && next.ends_with('{') {
                // Skip the test module: to the brace that closes it.
                let mut depth = 0i64;
                for (_, l) in lines.by_ref() {
                    depth += l.matches('{').count() as i64 - l.matches('}').count() as i64;
                    if depth <= 0 && l.contains('}') {
                        break;
                    }
                }
            }
            continue;
        }
        let code = line.split("//").next().unwrap_or("");
        let mut rest = code;
        while let Some(at) = rest.find("crate::") {
            let before = rest[..at].chars().last();
            rest = &rest[at + "crate::".len()..];
            if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == '$') {
                continue;
            }
            if let Some(group) = rest.strip_prefix('{') {
                // `use crate::{a::X, b}`: every first name of the group.
                let group = group.split('}').next().unwrap_or("");
                for item in group.split(',') {
                    let name: String = item
                        .trim()
                        .chars()
                        .take_while(|c| c.is_alphanumeric() || *c == '_')
                        .collect();
                    if !name.is_empty() {
                        out.push((i + 1, name));
                    }
                }
                continue;
            }
            let name: String = rest
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            if !name.is_empty() {
                out.push((i + 1, name));
            }
        }
    }
    out.into_iter()
        .map(|(line, name)| {
            if modules.contains(&name) {
                (line, name)
            } else {
                (line, "lib".to_string())
            }
        })
        .collect()
}

/// The imports of the library at `src` that run up or sideways by the
/// floors, as `file:line: floor A imports floor B`; and the library's
/// modules the table leaves out or names twice.
fn upward_imports(src: &Path, floors: &[(u32, Vec<String>)]) -> Vec<String> {
    let mut problems = Vec::new();
    let mut floor_of: Vec<(String, u32)> = Vec::new();
    for (floor, rooms) in floors {
        for room in rooms {
            if src.join(room.trim_end_matches('/')).exists() {
                let m = module_name(room);
                if floor_of.iter().any(|(n, _)| *n == m) {
                    problems.push(format!("`{room}` stands on two floors"));
                }
                floor_of.push((m, *floor));
            }
        }
    }
    let mut entries: Vec<PathBuf> = fs::read_dir(src)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    let modules: Vec<String> = entries
        .iter()
        .map(|p| module_name(&p.file_name().unwrap().to_string_lossy()))
        .collect();
    for m in &modules {
        if !floor_of.iter().any(|(n, _)| n == m) {
            problems.push(format!("module `{m}` of {} is on no floor", src.display()));
        }
    }
    for (path, module) in entries.iter().zip(&modules) {
        if module == "lib" {
            continue;
        }
        let Some(&(_, floor)) = floor_of.iter().find(|(n, _)| n == module) else {
            continue;
        };
        let mut files = Vec::new();
        sources(path, &mut files);
        files.sort();
        for file in files {
            if file.file_stem().is_some_and(|s| s == "tests") {
                continue;
            }
            let text = read(&file);
            for (line, used) in crate_paths(&text, &modules) {
                if used == *module {
                    continue;
                }
                let used_floor = floor_of
                    .iter()
                    .find(|(n, _)| *n == used)
                    .map_or(u32::MAX, |&(_, f)| f);
                if used_floor >= floor {
                    problems.push(format!(
                        "{}:{line}: `{module}` (floor {floor}) imports `{used}` (floor {used_floor})",
                        file.strip_prefix(src).unwrap_or(&file).display()
                    ));
                }
            }
        }
    }
    problems
}

/// The code spans of a Markdown text that look like paths of the
/// repository: a name with a `/` or a source or page extension, no blanks
/// and nothing of a pattern or an expression; absolute paths (the
/// machine's, not the repository's) left out. Names of files packbed
/// writes are not paths of the repository: the pages write them in
/// italics, not in code.
fn named_paths(markdown: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    for (n, line) in prose(markdown) {
        for span in code_spans(line) {
            let looks = span.contains('/')
                || [".rs", ".md", ".py", ".sh", ".toml", ".pyi"]
                    .iter()
                    .any(|e| span.ends_with(e));
            let refused = span.is_empty()
                || span.starts_with('-')
                || span.starts_with('/')
                || (span.starts_with('.') && !span.contains('/'))
                || span.starts_with("http")
                || span.contains("://")
                || span.contains("..")
                || !span.chars().any(|c| c.is_ascii_lowercase())
                || span.chars().any(|c| {
                    c.is_whitespace() || "*|<>{}()=,;:#%$&^+'\"[]".contains(c) || !c.is_ascii()
                });
            if looks && !refused {
                out.push((n, span.to_string()));
            }
        }
    }
    out
}

/// Every path of the repository (directories with a trailing `/`), relative
/// to `root`, build output and Git's own files left out.
fn repo_paths(root: &Path, dir: &Path, out: &mut Vec<String>) {
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let p = entry.path();
        if p.file_name()
            .is_some_and(|n| n == "target" || n == ".git" || n == "node_modules")
        {
            continue;
        }
        let rel = p.strip_prefix(root).unwrap().to_string_lossy().to_string();
        if p.is_dir() {
            out.push(format!("{rel}/"));
            repo_paths(root, &p, out);
        } else {
            out.push(rel);
        }
    }
}

/// Whether a named path exists: as a path from the repository's root, or as
/// the tail of one (`analysis/pores/flow.rs`, `triangulation/split.rs`,
/// `tables.rs`), as the map names paths under `crates/packbed/src/`.
fn exists(name: &str, paths: &[String]) -> bool {
    let dir = name.ends_with('/');
    let bare = name.trim_end_matches('/');
    paths.iter().any(|p| {
        let (p, is_dir) = match p.strip_suffix('/') {
            Some(d) => (d, true),
            None => (p.as_str(), false),
        };
        (!dir || is_dir) && (p == bare || p.ends_with(&format!("/{bare}")))
    })
}

/// The pages whose named paths are checked: ARCHITECTURE.md, then
/// docs/design/*.md in name order.
fn map_pages(root: &Path) -> Vec<PathBuf> {
    let mut design: Vec<PathBuf> = fs::read_dir(root.join("docs/design"))
        .map(|d| d.flatten().map(|e| e.path()).collect())
        .unwrap_or_default();
    design.retain(|p| p.extension().is_some_and(|e| e == "md"));
    design.sort();
    let mut all = vec![root.join("ARCHITECTURE.md")];
    all.extend(design);
    all
}

#[test]
fn the_front_pages_stay_short() {
    let root = root();
    let mut long = Vec::new();
    for (page, most) in [
        ("ARCHITECTURE.md", 400),
        ("README.md", 350),
        ("BENCHMARKS.md", 600),
    ] {
        let n = read(&root.join(page)).lines().count();
        if n > most {
            long.push(format!("{page}: {n} lines, at most {most}"));
        }
    }
    assert!(long.is_empty(), "{}", long.join("\n"));
}

#[test]
fn the_maps_sizes_are_the_codes() {
    let root = root();
    let map = read(&root.join("ARCHITECTURE.md"));
    assert!(size_claims(&map).len() >= 10, "the map states few sizes");
    let wrong = wrong_sizes(&root, &map);
    assert!(wrong.is_empty(), "ARCHITECTURE.md:\n{}", wrong.join("\n"));
}

#[test]
fn imports_run_only_down_the_maps_floors() {
    let root = root();
    let floors = floors(&read(&root.join("ARCHITECTURE.md")));
    let problems = upward_imports(&root.join("crates/packbed/src"), &floors);
    assert!(
        problems.is_empty(),
        "ARCHITECTURE.md's floors are not the code's:\n{}",
        problems.join("\n")
    );
}

#[test]
fn the_paths_the_map_and_the_design_pages_name_exist() {
    let root = root();
    let mut paths = Vec::new();
    repo_paths(&root, &root, &mut paths);
    let mut missing = Vec::new();
    let mut checked = 0;
    for page in map_pages(&root) {
        let name = page.strip_prefix(&root).unwrap().display().to_string();
        for (line, path) in named_paths(&read(&page)) {
            checked += 1;
            if !exists(&path, &paths) {
                missing.push(format!("{name}:{line}: `{path}`"));
            }
        }
    }
    assert!(checked > 50, "only {checked} paths named");
    assert!(
        missing.is_empty(),
        "paths named that the repository does not hold:\n{}",
        missing.join("\n")
    );
}

/// The checks find what they exist to find: a size off by more than the
/// tolerance, an import up a floor, a module on no floor, a path that is not.
#[test]
fn a_false_claim_is_found() {
    let dir = std::env::temp_dir().join(format!("packbed-architecture-{}", std::process::id()));
    let src = dir.join("src");
    fs::create_dir_all(src.join("low")).unwrap();
    fs::write(src.join("low/mod.rs"), "pub fn f() {}\n".repeat(10)).unwrap();
    fs::write(
        src.join("high.rs"),
        "use crate::low::f;\n// crate::top::x in a comment\n#[cfg(test)]\nmod tests {\n    use crate::top::T;\n}\n",
    )
    .unwrap();
    fs::write(src.join("top.rs"), "use crate::{high::g, Error};\n").unwrap();
    fs::write(src.join("lib.rs"), "pub mod low;\n").unwrap();

    let map = "| path | files | lines |\n| --- | --- | --- |\n| `src/low/` | 1 | 10 |\n| `src/high.rs` | 1 | 20 |\n";
    let wrong = wrong_sizes(&dir, map);
    assert_eq!(wrong.len(), 1, "{wrong:?}");
    assert!(wrong[0].contains("`src/high.rs` has 6 lines"), "{wrong:?}");

    let table = "| floor | rooms |\n| --- | --- |\n| 3 | `lib.rs` |\n| 2 | `high.rs`, `top.rs` |\n| 1 | `low/` |\n";
    let problems = upward_imports(&src, &floors(table));
    assert_eq!(
        problems,
        [
            "top.rs:1: `top` (floor 2) imports `high` (floor 2)",
            "top.rs:1: `top` (floor 2) imports `lib` (floor 3)",
        ]
    );
    fs::write(src.join("top.rs"), "use crate::{high::g, low};\n").unwrap();
    let fine = "| floor | rooms |\n| --- | --- |\n| 4 | `lib.rs` |\n| 3 | `top.rs` |\n| 2 | `high.rs` |\n| 1 | `low/` |\n";
    assert_eq!(upward_imports(&src, &floors(fine)), [] as [String; 0]);
    let partial =
        "| floor | rooms |\n| --- | --- |\n| 4 | `lib.rs` |\n| 3 | `top.rs` |\n| 1 | `low/` |\n";
    assert!(upward_imports(&src, &floors(partial))
        .iter()
        .any(|p| p.contains("module `high`") && p.contains("on no floor")));

    let mut paths = Vec::new();
    repo_paths(&dir, &dir, &mut paths);
    let named = named_paths(
        "See `src/low/mod.rs`, `low/`, `high.rs`, `gone/x.rs`, `summary.json` and `a / b`.",
    );
    let missing: Vec<&str> = named
        .iter()
        .filter(|(_, p)| !exists(p, &paths))
        .map(|(_, p)| p.as_str())
        .collect();
    assert_eq!(missing, ["gone/x.rs"]);
    fs::remove_dir_all(&dir).unwrap();
}
