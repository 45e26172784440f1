//! How passes append paths to queues (`--append`): one atomic per lane on the queue's counter, or
//! one per subgroup and queue (`shaders/wavefront/shared/append_subgroup.wgsl`). On a GPU, thousands of
//! lanes appending to one counter serialise on it; aggregating per subgroup divides the atomics
//! by the subgroup width (up to 32 on NVIDIA) at the cost of a few subgroup operations.

use super::super::context::GpuContext;
use crate::options::Append;
use anyhow::{bail, Result};

impl Append {
    /// Whether appends are aggregated per subgroup on `ctx`'s adapter; an error if asked for and
    /// missing.
    pub fn uses_subgroups(self, ctx: &GpuContext) -> Result<bool> {
        match self {
            Append::Auto => Ok(ctx.summary.subgroups),
            Append::Lane => Ok(false),
            Append::Subgroup if ctx.summary.subgroups => Ok(true),
            Append::Subgroup => bail!(
                "--append subgroup needs subgroup operations, which {} lacks; use --append auto",
                ctx.summary.name
            ),
        }
    }
}
