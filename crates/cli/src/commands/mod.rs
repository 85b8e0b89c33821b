//! One module per subcommand; each has `Args` (clap) and `run(Args) -> anyhow::Result<i32>`.

pub mod info;
// Called by `info` for `.bvh` files once that command dispatches on the extension.
#[allow(dead_code)]
pub mod bvh_info;
pub mod keyframes;
