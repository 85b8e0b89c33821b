//! One module per subcommand; each has `Args` (clap) and `run(Args) -> anyhow::Result<i32>`.

pub mod convert;
pub mod diff;
pub mod export;
pub mod info;
pub mod plot;
pub mod view;
