//! What packbed prints on screen: the texts of every command, in one place,
//! at the top of the house (they read the summaries of runs, analyses,
//! fragmentations and ensembles, and nothing below writes them).

mod ensemble;
mod run;

pub use ensemble::{ensemble_text, reduced_note};
pub use run::{
    analyze_text, file_names, fragment_text, overlap_warning, path, run_text, warning_lines,
};

/// A text for the screen (several lines): every character that acts on a
/// terminal escaped as `crate::error::echo` escapes it, the line breaks
/// kept. The last guard before stdout; a value inside a line (a name, a
/// path) is escaped where it is written, its line breaks too.
pub fn screen(text: &str) -> String {
    text.split('\n')
        .map(crate::error::inert)
        .collect::<Vec<_>>()
        .join("\n")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::{markdown_cell, xml_text};

    /// A name with every troublesome character: ESC (a colour), an OSC
    /// (window title) ended by BEL, the C1 CSI U+009B, markup and a newline.
    pub(crate) const HOSTILE: &str = "a\u{1b}[31m\u{1b}]0;t\u{7}\u{9b}2J<&>|\"'\nb";

    #[test]
    fn screen_text_keeps_its_lines_and_escapes_the_rest() {
        let t = screen("x \u{1b}[2J\ny\u{9b}\u{7}\n");
        assert_eq!(t, "x \\u{1b}[2J\ny\\u{9b}\\u{7}\n");
    }

    #[test]
    fn xml_text_is_well_formed_xml() {
        let x = xml_text(HOSTILE);
        assert_eq!(
            x,
            "a\\u{1b}[31m\\u{1b}]0;t\\u{7}\\u{9b}2J&lt;&amp;&gt;|&quot;&apos;\\u{a}b"
        );
        assert!(x.chars().all(|c| !c.is_control()), "{x}");
        assert_eq!(xml_text("\u{fffe}"), "\\u{fffe}");
    }

    #[test]
    fn a_markdown_cell_adds_no_column_and_no_line() {
        let m = markdown_cell(HOSTILE);
        assert_eq!(
            m,
            "a\\u{1b}[31m\\u{1b}]0;t\\u{7}\\u{9b}2J&lt;&amp;>\\|\"'\\u{a}b"
        );
        // Every `|` is escaped: a table row keeps its columns.
        assert!(!m.replace("\\|", "").contains('|'), "{m}");
        assert_eq!(markdown_cell(r"a\|b_c"), r"a\\\|b_c");
    }
}
