//! Uniform cell grid for neighbour queries.
