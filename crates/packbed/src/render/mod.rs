//! Pictures of beds and plots of measures.
