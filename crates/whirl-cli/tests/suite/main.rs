//! The command line's integration tests, one test binary: each file a module, named after
//! it (`cargo test -p whirl-cli --test suite fuzz::` runs the fuzzer's). One binary links
//! the library once, where one per file re-linked it for each after every change to the
//! library, and lets libtest run every file's tests in one parallel pool.

// The shared test models of the library's tests; the command line's tests use a part.
#[allow(dead_code)]
#[path = "../../../whirl/tests/suite/common/reference.rs"]
mod reference;

mod bad_input;
mod cascade;
mod commands;
mod firstday;
mod fit_forcing;
mod fuzz;
mod hbm;
mod import_ross;
mod map;
mod reliability;
mod runup;
mod simulate;
mod stiffness;
mod study;
