//! The one error type of the library: every variant is a user-facing problem
//! (bad config, unreadable file, impossible request) reported with exit code 2.

use std::path::PathBuf;

/// Everything that can go wrong because of what the user asked for.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The configuration is invalid; the message names the key.
    #[error("config: {0}")]
    Config(String),
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file concerned.
        path: PathBuf,
        /// What the operating system said.
        source: std::io::Error,
    },
    /// A data file (PSD table, bed file) has bad content; names file and line.
    #[error("{path}:{line}: {message}")]
    Data {
        /// The file concerned.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What is wrong on that line.
        message: String,
    },
    /// The request cannot be carried out (e.g. would need too much memory).
    #[error("{0}")]
    Impossible(String),
    /// The caller asked the work to stop (Ctrl-C in Python) before it ended.
    #[error("interrupted")]
    Interrupted,
    /// A setting given with the request (not in the config file) is wrong:
    /// `runs`, `jobs`, `shard`, `out`, `export`. The command names it as its
    /// option (`--runs`), the Python package as its keyword.
    #[error("{setting}: {message}")]
    Setting {
        /// The setting's name.
        setting: &'static str,
        /// What is wrong with it.
        message: String,
    },
}

/// Result with packbed's [`Error`].
pub type Result<T> = std::result::Result<T, Error>;

impl Error {
    /// A configuration error.
    pub(crate) fn config(msg: impl Into<String>) -> Self {
        Error::Config(msg.into())
    }

    /// An error in the setting `setting` of the request.
    pub(crate) fn setting(setting: &'static str, msg: impl Into<String>) -> Self {
        Error::Setting {
            setting,
            message: msg.into(),
        }
    }

    /// The same error placed under a setting: `within("ratio")` turns the
    /// config error "3 values …" into "ratio: 3 values …"; other errors, which
    /// name their file, are kept as they are.
    pub fn within(self, place: &str) -> Self {
        match self {
            Error::Config(m) => Error::Config(format!("{place}: {m}")),
            other => other,
        }
    }

    /// The message without the "config: " tag.
    pub fn message(&self) -> String {
        match self {
            Error::Config(m) => m.clone(),
            other => other.to_string(),
        }
    }
}

/// The one line a user sees for an error and its causes (the command prints
/// it after `packbed: error: `; the Python package raises it): `FILE:LINE:
/// what` when it has a place in a file, else the causes joined as "what: why".
/// A place found under a context (the config that named a PSD table, say)
/// still leads, the context following in parentheses, so that every error
/// with a line has the same shape.
pub fn one_line(e: &(dyn std::error::Error + 'static)) -> String {
    one_line_naming(e, &|setting| setting.to_string())
}

/// [`one_line`], with the settings of [`Error::Setting`] named by `name`
/// (the command: `--runs`).
pub fn one_line_naming(
    e: &(dyn std::error::Error + 'static),
    name: &dyn Fn(&str) -> String,
) -> String {
    let causes: Vec<&(dyn std::error::Error + 'static)> =
        std::iter::successors(Some(e), |c| c.source()).collect();
    let placed = causes
        .iter()
        .position(|c| matches!(c.downcast_ref::<Error>(), Some(Error::Data { .. })));
    let text = match placed {
        Some(k) if k > 0 => {
            let outer: Vec<String> = causes[..k].iter().map(|c| text_of(*c, name)).collect();
            format!("{} (in {})", joined(&causes[k..], name), outer.join(": "))
        }
        _ => joined(&causes, name),
    };
    clean_line(&text)
}

/// The warning for a picture `name` left out of a run because `why`.
pub fn picture_not_written(name: &str, why: &Error) -> String {
    format!("picture {name} not written ({why}); the other files are complete")
}

/// Characters of an input value [`echo`] keeps before cutting it.
pub const ECHO_CHARS: usize = 60;

/// A word of a message longer than this is cut by [`clean_line`]: the last
/// guard against a value that reached a message without [`echo`].
const LINE_WORD_CHARS: usize = 200;

/// An input value (a field of a bed file, a species name, an option's text)
/// as a message may show it: control and invisible formatting characters
/// escaped (`\u{1b}`), so that nothing from a file acts on the terminal, and
/// cut after [`ECHO_CHARS`] characters with its length in bytes, so that a
/// 50 MB field gives a short line. The caller adds its quotes.
pub fn echo(value: &str) -> String {
    cut(value, ECHO_CHARS)
}

/// `value` with every character [`echo`] escapes escaped, uncut: a path or
/// a name shown whole, nothing in it acting on a terminal or starting a line.
pub fn inert(value: &str) -> String {
    cut(value, usize::MAX)
}

fn cut(value: &str, keep: usize) -> String {
    let mut out = String::new();
    for (k, c) in value.chars().enumerate() {
        if k == keep {
            out.push_str(&format!("…({} bytes)", value.len()));
            break;
        }
        if hidden(c) {
            out.extend(c.escape_unicode());
        } else {
            out.push(c);
        }
    }
    out
}

/// Characters that move the cursor, recolour or reorder text on a terminal
/// (C0 and C1 controls, bidirectional and zero-width formatting), and the
/// noncharacters U+FFFE and U+FFFF, which XML forbids.
fn hidden(c: char) -> bool {
    c.is_control()
        || matches!(c, '\u{200b}'..='\u{200f}' | '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}' | '\u{feff}' | '\u{fffe}' | '\u{ffff}')
}

/// A path for a message or the screen: whole, nothing in it acting on the
/// terminal (`inert`).
pub fn inert_path(p: &std::path::Path) -> String {
    inert(&p.display().to_string())
}

/// `text` as XML character data or an attribute value (SVG): `& < > " '` as
/// entities, and the characters XML 1.0 forbids even as references (controls
/// other than tab and line breaks) or that act on a terminal written as
/// visible escapes (`\u{1b}`), as [`echo`] shows them.
#[cfg_attr(not(feature = "render"), allow(dead_code))]
pub fn xml_text(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in inert(text).chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c => out.push(c),
        }
    }
    out
}

/// `text` as one cell of a Markdown table (or a heading's text): `\` and `|`
/// escaped with a backslash, `<` and `&` as entities (no HTML), and line
/// breaks and control characters as visible escapes (`\u{a}`), so that a
/// name never adds a column or a line.
pub fn markdown_cell(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '\\' | '|' => {
                out.push('\\');
                out.push(c);
            }
            '<' => out.push_str("&lt;"),
            '&' => out.push_str("&amp;"),
            c => out.push(c),
        }
    }
    inert(&out)
}

/// `text` as one clean line: whitespace runs (newlines too) become one
/// blank, and every word is shown as [`echo`] shows a value, cut at a
/// generous length, so an error or a warning is one short line whatever a
/// file held.
pub fn clean_line(text: &str) -> String {
    // Parsers' messages may span lines; a script reading stderr wants one.
    text.split_whitespace()
        .map(|w| cut(w, LINE_WORD_CHARS))
        .collect::<Vec<_>>()
        .join(" ")
}

/// The causes as "what: why", leaving out a cause whose text the message
/// already quotes (I/O errors include their source). A config error under a
/// context (the file, or "command-line options") drops its "config: " tag:
/// the context already says where the setting came from.
fn joined(causes: &[&(dyn std::error::Error + 'static)], name: &dyn Fn(&str) -> String) -> String {
    let mut text = String::new();
    for (k, cause) in causes.iter().enumerate() {
        let c = match cause.downcast_ref::<Error>() {
            Some(Error::Config(m)) if k > 0 => m.clone(),
            _ => text_of(*cause, name),
        };
        if !text.contains(&c) {
            if !text.is_empty() {
                text.push_str(": ");
            }
            text.push_str(&c);
        }
    }
    text
}

/// One cause as text, a setting named by `name`.
fn text_of(cause: &(dyn std::error::Error + 'static), name: &dyn Fn(&str) -> String) -> String {
    match cause.downcast_ref::<Error>() {
        Some(Error::Setting { setting, message }) => format!("{}: {message}", name(setting)),
        _ => cause.to_string(),
    }
}

/// A usage error as an argument parser writes it (what is wrong over several
/// lines, then a usage block and a pointer to the help) folded into one line:
/// `what is wrong (usage: …)`.
pub fn usage_line(text: &str) -> String {
    let mut what = Vec::new();
    let mut usage = None;
    for line in text
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with("For more information"))
    {
        if let Some(u) = line.strip_prefix("Usage: ") {
            usage = Some(u.to_string());
            break;
        }
        what.push(line.strip_prefix("error: ").unwrap_or(line));
    }
    let what = if what.is_empty() {
        "invalid arguments".to_string()
    } else {
        what.join(" ")
    };
    match usage {
        Some(u) => format!("{what} (usage: {u})"),
        None => format!("{what} (see `packbed --help`)"),
    }
}

/// The one line a panic becomes: a bug in packbed, never the user's fault,
/// said without the default advice to set RUST_BACKTRACE.
pub fn panic_line(info: &std::panic::PanicHookInfo<'_>) -> String {
    let payload = info.payload();
    let msg = payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".into());
    let at = info
        .location()
        .map(|l| format!(" at {}:{}", l.file(), l.line()))
        .unwrap_or_default();
    format!(
        "internal error (a bug in packbed, please report it): {}{at}",
        msg.split_whitespace().collect::<Vec<_>>().join(" ")
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_usage_error_folds_into_one_line() {
        let clap = "error: unexpected argument '--bogus' found\n\n  tip: use '-- --bogus'\n\n\
                    Usage: packbed run [OPTIONS]\n\nFor more information, try '--help'.\n";
        assert_eq!(
            usage_line(clap),
            "unexpected argument '--bogus' found tip: use '-- --bogus' (usage: packbed run [OPTIONS])"
        );
        assert_eq!(usage_line("\n"), "invalid arguments (see `packbed --help`)");
    }

    /// A context over an error, as a caller's `with_context` makes one.
    #[derive(Debug)]
    struct Within(&'static str, Error);

    impl std::fmt::Display for Within {
        fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            f.write_str(self.0)
        }
    }

    impl std::error::Error for Within {
        fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
            Some(&self.1)
        }
    }

    #[test]
    fn a_config_error_says_config_once() {
        let bare = Error::config("box.width must be a positive number, got 0");
        assert_eq!(
            one_line(&bare),
            "config: box.width must be a positive number, got 0"
        );
        let placed = Within("command-line options", bare);
        assert_eq!(
            one_line(&placed),
            "command-line options: box.width must be a positive number, got 0"
        );
        let io = Within("run", Error::Impossible("too large".into()));
        assert_eq!(one_line(&io), "run: too large");
    }

    #[test]
    fn echoed_values_are_short_and_inert() {
        assert_eq!(echo("1.5e3"), "1.5e3");
        assert_eq!(echo("a\u{1b}[31mb\u{7}"), "a\\u{1b}[31mb\\u{7}");
        assert_eq!(echo("x\u{202e}y"), "x\\u{202e}y");
        let long = "é".repeat(100);
        assert_eq!(echo(&long), format!("{}…(200 bytes)", "é".repeat(60)));
        let line = clean_line(&format!("bad\n value {}\u{1b}", "9".repeat(1000)));
        assert_eq!(line, format!("bad value {}…(1001 bytes)", "9".repeat(200)));
    }
}
