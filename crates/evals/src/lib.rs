//! What the evaluations share: the corpus trials they run on and how a trial is read
//! ([`corpus`]), the labs a result is reported by ([`labs`]), the order statistics of their
//! tables ([`stats`]), the step rule read back through the file ([`step`]) and the fit of
//! `auto`'s expected-error model ([`fit`]).
//!
//! The evaluations themselves are the binaries of `src/bin` (`fill_eval`, `swap_eval`,
//! `events_eval`, `plates_eval`, `step_check`): `cargo run --release -p evals --bin NAME --
//! --help`. None of this ships: the library crates know nothing of it, and the only thing
//! it gives back to them is the generated coefficients file `repair` compiles.

pub mod corpus;
pub mod dice;
pub mod fit;
pub mod labs;
pub mod stats;
pub mod step;
