//! The command's integration tests, one binary: each test runs the built
//! `packbed` in a scratch directory and checks exit code, messages and files.
//! The harness (scratch directory, run, compare) is [`common`].

mod common;

mod agglomeration;
mod architecture;
mod bounds;
mod commands;
mod compare;
mod docs_examples;
mod drainage;
mod ensemble;
mod escapes;
mod files;
mod filtration;
mod filtration_studies;
mod fragment;
mod front_door;
mod output_dir;
mod pores;
mod python;
mod render;
mod sizes;
mod slurm;
