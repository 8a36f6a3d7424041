//! Measures of a bed's structure.
