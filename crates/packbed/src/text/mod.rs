//! What packbed prints on screen: the texts of every command, in one place,
//! at the top of the house (they read the summaries of runs, analyses,
//! fragmentations and ensembles, and nothing below writes them).

mod ensemble;
mod run;

pub use ensemble::{ensemble_text, reduced_note};
pub use run::{analyze_text, file_names, fragment_text, overlap_warning, run_text, warning_lines};

/// A value as one cell of a Markdown table (or an item of a list): `|`, `\`,
/// `` ` `` and the `<` of a tag escaped with a backslash, so that a name
/// cannot end the cell, open a code span or an HTML tag, and control
/// characters shown as `\u{1b}`, so that a newline cannot end the row.
pub fn markdown_cell(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        let tag = c == '<'
            && chars
                .peek()
                .is_some_and(|n| n.is_alphabetic() || matches!(n, '/' | '!' | '?'));
        match c {
            '|' | '\\' | '`' => {
                out.push('\\');
                out.push(c);
            }
            '<' if tag => {
                out.push('\\');
                out.push(c);
            }
            c if c.is_control() => {
                out.push('\\');
                out.extend(c.escape_unicode());
            }
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_markdown_cell_holds_any_name() {
        let cell = super::markdown_cell("a|b\nc`d\\e\u{1b}[31m<x>");
        assert_eq!(cell, "a\\|b\\\\u{a}c\\`d\\\\e\\\\u{1b}[31m\\<x>");
        assert!(!cell.contains('\n') && !cell.contains('\u{1b}'));
        assert_eq!(super::markdown_cell("p < 0.05"), "p < 0.05");
    }
}
