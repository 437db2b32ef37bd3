//! The library's integration tests, one test binary: each file a module, named after it
//! (`cargo test -p whirl-rotordynamics --test suite hbm::` runs the harmonic balance's).
//! One binary links the library once, where one per file re-linked it for each after every
//! change to the library, and lets libtest run every file's tests in one parallel pool.
//!
//! The tests share the process: a test that changes process-wide state (faer's global
//! parallelism, the environment, the working directory) changes it for all of them.

mod common;

mod ball_bearing;
mod bearing;
mod bearing_frequencies;
mod bearing_life;
mod bearing_stiffness;
mod campbell;
mod cascade;
mod docs;
mod elements;
mod firstday;
mod force_laws;
mod forcing;
mod frf;
mod hbm;
mod hbm_bifurcation;
mod hbm_condensation;
mod hbm_model;
mod housings;
mod implicit_contacts;
mod integrators;
mod lagrange;
mod layers;
mod map;
mod race_defect;
mod refused_answers;
mod ring_waviness;
mod roller_simulation;
mod ross;
mod runup;
mod spectrum;
mod squeeze_film;
mod statics;
mod study_file;
mod study_run;
mod timoshenko;
mod unbalance;
