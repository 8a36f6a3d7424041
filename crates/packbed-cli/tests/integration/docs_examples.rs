//! The shell examples of README.md and the user guide (docs/guide/*.md) run,
//! the documents' relative links resolve (docs/reference/*.md too), and the
//! pages source comments name exist.
//!
//! Convention: a fenced block opened with ```` ```sh ```` one of whose
//! commands calls `packbed` is an example, and this test runs it: the whole
//! block, as one `sh -e` script, with the built `packbed` first on `PATH`, and
//! it must exit 0. The blocks of one page run in order in one scratch
//! directory, as a reader would type them, holding a copy of the repository's
//! `examples/` and an empty `docs/` (so that `examples/…` inputs resolve and
//! pictures written to `docs/…` land in the scratch directory, not the
//! repository's). A block that cannot run here is fenced ```` ```sh no-run ````
//! and the text beside it says why: one that needs Slurm, or one too slow for
//! a test (an ensemble of many large beds, a benchmark of a million
//! particles). Use it sparingly: prefer a small example that runs. Any other
//! info string starting with `sh` is refused, so that a misspelt `no-run`
//! does not hide an example. Blocks of other tools (`cargo`, `pip`,
//! `scripts/…`) are not this test's; `python` blocks are the Python suite's
//! business (crates/packbed-cli/tests/integration/python.rs).

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Instant;

/// One fenced shell block of a page.
#[derive(Debug)]
struct Block {
    /// The line of its opening fence (1-based).
    line: usize,
    /// Fenced ```` ```sh no-run ````.
    no_run: bool,
    text: String,
}

/// Whether a shell line calls `packbed` (comments aside): as its first word or
/// after `do`, `;`, `&&`, `|` and the like.
fn calls_packbed(line: &str) -> bool {
    let code = match line.trim_start().strip_prefix('#') {
        Some(_) => return false,
        None => line.split(" #").next().unwrap_or(""),
    };
    code.split(|c: char| c.is_whitespace() || ";&|(".contains(c))
        .any(|word| word == "packbed")
}

/// The packbed commands of a block (a `\` continuation joins its lines).
fn commands(block: &Block) -> Vec<String> {
    let mut found = Vec::new();
    let mut pending = String::new();
    for line in block.text.lines() {
        pending.push_str(line.trim_end_matches('\\'));
        if line.ends_with('\\') {
            continue;
        }
        if calls_packbed(&pending) {
            found.push(pending.trim().to_string());
        }
        pending.clear();
    }
    found
}

/// The ```` ```sh ```` blocks of a Markdown text that call `packbed`; refuses an
/// info string that starts with `sh` but is neither `sh` nor `sh no-run`.
fn shell_examples(markdown: &str, name: &str) -> Result<Vec<Block>, String> {
    let mut blocks = Vec::new();
    let mut lines = markdown.lines().enumerate();
    while let Some((i, line)) = lines.next() {
        let Some(info) = line.trim_start().strip_prefix("```") else {
            continue;
        };
        let info = info.trim();
        let mut text = String::new();
        for (_, inner) in lines.by_ref() {
            if inner.trim_start().starts_with("```") {
                break;
            }
            text.push_str(inner);
            text.push('\n');
        }
        let no_run = match info {
            "sh" => false,
            "sh no-run" => true,
            _ if info.starts_with("sh") => {
                return Err(format!(
                    "{name}:{}: fence info string {info:?}: use `sh` or `sh no-run`",
                    i + 1
                ))
            }
            _ => continue,
        };
        let block = Block {
            line: i + 1,
            no_run,
            text,
        };
        if !commands(&block).is_empty() {
            blocks.push(block);
        }
    }
    Ok(blocks)
}

fn copy_dir(from: &Path, to: &Path) {
    fs::create_dir_all(to).unwrap();
    for entry in fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        let target = to.join(entry.file_name());
        if entry.file_type().unwrap().is_dir() {
            copy_dir(&entry.path(), &target);
        } else {
            fs::copy(entry.path(), &target).unwrap();
        }
    }
}

/// README.md, then the guide's pages in name order.
fn pages(root: &Path) -> Vec<PathBuf> {
    let mut guide: Vec<PathBuf> = fs::read_dir(root.join("docs/guide"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    guide.sort();
    let mut all = vec![root.join("README.md")];
    all.extend(guide);
    all
}

/// The pages whose links are checked: those of [`pages`], then the reference
/// pages (docs/reference/*.md) in name order, ARCHITECTURE.md and the design
/// records (docs/design/*.md). These hold no examples to run.
fn linked_pages(root: &Path) -> Vec<PathBuf> {
    let mut all = pages(root);
    for dir in ["docs/reference", "docs/design"] {
        let mut more: Vec<PathBuf> = fs::read_dir(root.join(dir))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "md"))
            .collect();
        more.sort();
        all.extend(more);
        if dir == "docs/reference" {
            all.push(root.join("ARCHITECTURE.md"));
        }
    }
    all
}

#[test]
fn the_documents_shell_examples_run() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let bin = Path::new(env!("CARGO_BIN_EXE_packbed"));
    let path = std::env::join_paths(std::iter::once(bin.parent().unwrap().to_path_buf()).chain(
        std::env::split_paths(&std::env::var_os("PATH").unwrap_or_default()),
    ))
    .unwrap();
    let (mut ran, mut skipped, mut ran_commands) = (0, 0, 0);
    let mut failures = Vec::new();
    for page in pages(&root) {
        let name = page.strip_prefix(&root).unwrap().display().to_string();
        let blocks = shell_examples(&fs::read_to_string(&page).unwrap(), &name).unwrap();
        let scratch = tempfile::tempdir().unwrap();
        copy_dir(&root.join("examples"), &scratch.path().join("examples"));
        fs::create_dir(scratch.path().join("docs")).unwrap();
        for block in &blocks {
            if block.no_run {
                skipped += 1;
                eprintln!("{name}:{}: no-run", block.line);
                continue;
            }
            let start = Instant::now();
            let out = Command::new("sh")
                .args(["-e", "-c", &block.text])
                .current_dir(scratch.path())
                .env("PATH", &path)
                .stdin(Stdio::null())
                .output()
                .unwrap();
            ran += 1;
            ran_commands += commands(block).len();
            eprintln!(
                "{name}:{}: {:.1} s: {}",
                block.line,
                start.elapsed().as_secs_f64(),
                commands(block).join(" ; ")
            );
            if !out.status.success() {
                let stderr = String::from_utf8_lossy(&out.stderr);
                let tail: Vec<&str> = stderr.lines().rev().take(5).collect();
                failures.push(format!(
                    "{name}:{}: {}\n{}\n  {}",
                    block.line,
                    out.status,
                    block.text.trim(),
                    tail.into_iter().rev().collect::<Vec<_>>().join("\n  ")
                ));
            }
        }
    }
    eprintln!("{ran} blocks ({ran_commands} packbed commands) run, {skipped} no-run");
    assert!(ran > 0, "no shell example found");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// GitHub's anchor of a heading: lower case, punctuation dropped (`-` and `_`
/// kept), blanks to `-`.
fn anchor(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || matches!(c, ' ' | '-' | '_'))
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}

/// The anchors of a Markdown file's headings (outside fenced blocks).
fn anchors(markdown: &str) -> Vec<String> {
    headings(markdown).iter().map(|h| anchor(h)).collect()
}

/// The targets of the inline links `[text](target)` of a Markdown text, with
/// their lines.
fn links(markdown: &str) -> Vec<(usize, String)> {
    let mut found = Vec::new();
    for (i, line) in markdown.lines().enumerate() {
        let mut rest = line;
        while let Some(at) = rest.find("](") {
            rest = &rest[at + 2..];
            if let Some(end) = rest.find(')') {
                found.push((i + 1, rest[..end].to_string()));
                rest = &rest[end..];
            }
        }
    }
    found
}

#[test]
fn the_documents_relative_links_resolve() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut broken = Vec::new();
    let mut checked = 0;
    for page in linked_pages(&root) {
        let text = fs::read_to_string(&page).unwrap();
        let name = page.strip_prefix(&root).unwrap().display().to_string();
        for (line, target) in links(&text) {
            if target.contains("://") || target.starts_with("mailto:") {
                continue;
            }
            checked += 1;
            let (file, fragment) = match target.split_once('#') {
                Some((f, a)) => (f, Some(a)),
                None => (target.as_str(), None),
            };
            let path = if file.is_empty() {
                page.clone()
            } else {
                page.parent().unwrap().join(file)
            };
            if !path.exists() {
                broken.push(format!("{name}:{line}: {target}: no such file"));
                continue;
            }
            if let Some(fragment) = fragment {
                let heads = anchors(&fs::read_to_string(&path).unwrap_or_default());
                if !heads.iter().any(|h| h == fragment) {
                    broken.push(format!("{name}:{line}: {target}: no such heading"));
                }
            }
        }
    }
    assert!(checked > 0, "no relative link found");
    assert!(broken.is_empty(), "{}", broken.join("\n"));
}

/// The Rust files under `dir`, in name order (build output left out).
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            if path.file_name().is_some_and(|n| n != "target") {
                rust_files(&path, out);
            }
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The text of a line's comment (`//`, `///`, `//!` at its start), if any.
fn comment(line: &str) -> Option<&str> {
    line.trim_start().strip_prefix("//")
}

/// What a comment names: the byte offsets where `word` starts a path (not
/// inside a longer word or path).
fn path_starts<'a>(text: &'a str, word: &'a str) -> impl Iterator<Item = usize> + 'a {
    text.match_indices(word)
        .map(|(at, _)| at)
        .filter(move |&at| {
            !text[..at]
                .chars()
                .next_back()
                .is_some_and(|c| c.is_alphanumeric() || matches!(c, '/' | '.' | '_' | '-'))
        })
}

/// The `docs/….md` paths a comment names, each with the section title quoted
/// right after it (`docs/reference/model.md`, "Filling"), if any.
fn doc_references(text: &str) -> Vec<(String, Option<String>)> {
    let mut found = Vec::new();
    for at in path_starts(text, "docs/") {
        let rest = &text[at..];
        let end = rest
            .find(|c: char| !(c.is_alphanumeric() || matches!(c, '/' | '.' | '_' | '-')))
            .unwrap_or(rest.len());
        let path = rest[..end].trim_end_matches('.');
        let path = if let Some(stem) = path.strip_suffix(".md") {
            format!("{stem}.md")
        } else {
            continue;
        };
        let after = rest[path.len()..].trim_start_matches('`');
        let title = after
            .strip_prefix(", \"")
            .and_then(|t| t.split_once('"'))
            .map(|(t, _)| t.to_string());
        found.push((path, title));
    }
    found
}

/// The titles of a Markdown file's headings (outside fenced blocks).
fn headings(markdown: &str) -> Vec<String> {
    let mut fenced = false;
    let mut found = Vec::new();
    for line in markdown.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
        } else if !fenced && line.starts_with('#') {
            found.push(line.trim_start_matches('#').trim().to_string());
        }
    }
    found
}

/// Comments say where a rule is written down, and it must be in the
/// repository: no comment under crates/ names the team's background notes
/// (a `spec` directory outside it), and every `docs/….md` page a comment names
/// exists, with the section it quotes.
#[test]
fn source_comments_point_at_pages_that_exist() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut files = Vec::new();
    rust_files(&root.join("crates"), &mut files);
    let outside = ["spec", "/"].concat();
    let mut wrong = Vec::new();
    let mut checked = 0;
    for file in &files {
        let text = fs::read_to_string(file).unwrap();
        let name = file.strip_prefix(&root).unwrap().display().to_string();
        for (i, line) in text.lines().enumerate() {
            let Some(c) = comment(line) else { continue };
            if path_starts(c, &outside).next().is_some() {
                wrong.push(format!(
                    "{name}:{}: names {outside}…, which is not in the repository: \
                     point at docs/ or say the rule here",
                    i + 1
                ));
            }
            for (path, title) in doc_references(c) {
                checked += 1;
                let Ok(page) = fs::read_to_string(root.join(&path)) else {
                    wrong.push(format!("{name}:{}: {path}: no such file", i + 1));
                    continue;
                };
                if let Some(title) = title {
                    if !headings(&page).contains(&title) {
                        wrong.push(format!("{name}:{}: {path}: no section \"{title}\"", i + 1));
                    }
                }
            }
        }
    }
    assert!(files.len() > 100, "only {} Rust files found", files.len());
    assert!(checked > 0, "no docs/ page named in a comment");
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

#[test]
fn the_examples_extractor_finds_runs_skips_and_refuses() {
    let md = "text\n```sh\npackbed run --out a   # a bed\nls a\n```\n\
              ```sh no-run\npackbed slurm x.toml --runs 5 \\\n    --tasks 2 --out s\n```\n\
              ```sh\ncargo test   # builds packbed\n```\n\
              ```\npackbed: error: not a shell block\n```\n\
              ```sh\nfor k in 0 1; do packbed ensemble --runs 2 --shard $k/2 --out p$k; done\n```\n";
    let blocks = shell_examples(md, "t.md").unwrap();
    assert_eq!(blocks.len(), 3, "{blocks:?}");
    assert_eq!((blocks[0].line, blocks[0].no_run), (2, false));
    assert_eq!(commands(&blocks[0]), ["packbed run --out a   # a bed"]);
    assert!(blocks[1].no_run);
    assert_eq!(
        commands(&blocks[1]),
        ["packbed slurm x.toml --runs 5     --tasks 2 --out s"]
    );
    assert!(commands(&blocks[2])[0].starts_with("for k in 0 1; do packbed"));
    assert_eq!(
        shell_examples("```sh norun\npackbed run\n```\n", "t.md").unwrap_err(),
        "t.md:1: fence info string \"sh norun\": use `sh` or `sh no-run`"
    );
    assert_eq!(
        anchor("Comparing beds: `packbed compare`"),
        "comparing-beds-packbed-compare"
    );
    assert_eq!(
        links("see [a](b.md#c) and [d](https://e/f)."),
        [(1, "b.md#c".to_string()), (1, "https://e/f".to_string())]
    );
    assert_eq!(
        doc_references(
            " (`docs/reference/model.md`, \"Filling\"); docs/guide/*.md; \
             see docs/validation.md. Not crates/x/docs/y.md"
        ),
        [
            (
                "docs/reference/model.md".to_string(),
                Some("Filling".to_string())
            ),
            ("docs/validation.md".to_string(), None),
        ]
    );
    assert_eq!(comment("    //! a"), Some("! a"));
    assert_eq!(comment("let a = \"//\";"), None);
    assert_eq!(path_starts("species/ and spec/x", "spec/").count(), 1);
}
