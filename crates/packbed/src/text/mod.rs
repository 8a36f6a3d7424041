//! What packbed prints on screen: the texts of every command, in one place,
//! at the top of the house (they read the summaries of runs, analyses,
//! fragmentations and ensembles, and nothing below writes them).

mod ensemble;
mod run;

pub use ensemble::{ensemble_text, reduced_note};
pub use run::{analyze_text, file_names, fragment_text, overlap_warning, run_text, warning_lines};
