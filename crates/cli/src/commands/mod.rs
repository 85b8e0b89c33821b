//! One module per subcommand; each has `Args` (clap) and `run(Args) -> anyhow::Result<i32>`.

pub mod batch;
pub mod bvh_info;
pub mod convert;
pub mod cycles;
pub mod destination;
pub mod diff;
pub mod each;
pub mod evaluate;
pub mod events;
pub mod export;
pub mod forces;
pub mod gait;
pub mod gaps;
pub mod info;
pub mod keyframes;
pub mod label;
pub mod parallel;
pub mod plot;
pub mod reclaim;
pub mod repair;
pub mod repair_io;
pub mod report;
pub mod swaps;
pub mod targets;
pub mod view;
