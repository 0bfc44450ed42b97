//! aqua-study: what runs a scene many times or draws its results, around the simulator
//! (aqua-sim), so that the simulator itself does not link the chart library.
//!
//! [`study`] runs a scene over ladders of settings and estimates converged values, errors and
//! the cheapest setting within a tolerance (`aqua study`); [`sweep`] expands a case file into
//! load cases and collects their run folders into one table (`aqua sweep`, `aqua collect`);
//! [`plot`] draws PNG charts of a run folder or a study (`aqua plot`, `aqua run --plot`).

pub mod local_runner;
pub mod plot;
pub mod study;
pub mod study_text;
pub mod sweep;
