//! What a streamed study keeps in memory: the estimate ([`MemoryEstimate`],
//! made by [`crate::Study::memory`]) and the refusal of a study that would
//! not fit ([`MemoryRefused`]).

/// What a streamed study keeps in memory ([`Study::memory`](crate::Study::memory)), bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MemoryEstimate {
    /// Kept for the whole study per run: one `f64` per measure for the
    /// summary's percentiles.
    pub kept_per_run: u64,
    /// Per run of the chunk being flown: its set-up (start, script), its
    /// fleet lane, its tracker and its table row.
    pub flying_per_run: u64,
    /// Runs flown at once (one chunk).
    pub chunk_runs: u64,
    /// The total: `runs × kept_per_run + chunk_runs × flying_per_run`.
    pub total: u64,
}

/// A study refused before it flies because it would not fit in memory
/// ([`MemoryEstimate::check`]).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum MemoryRefused {
    /// More than the caller's limit (`sim-cli study --memory-limit-mib`).
    #[error(
        "the study needs about {} MiB ({runs} runs × {} bytes kept + {} runs in flight × {} \
         bytes), more than --memory-limit-mib {limit_mib}",
        .estimate.total.div_ceil(1024 * 1024),
        .estimate.kept_per_run,
        .estimate.chunk_runs.min(*.runs),
        .estimate.flying_per_run
    )]
    OverLimit {
        /// The estimate.
        estimate: MemoryEstimate,
        /// The study's runs.
        runs: u64,
        /// The limit, MiB.
        limit_mib: u64,
    },
    /// More than this process can still allocate.
    #[error(
        "the study needs about {} MiB; this process has {} MiB available (the machine's \
         available memory, the address-space limit and the cgroup's memory limit)",
        .estimate.total.div_ceil(1024 * 1024),
        .available_bytes / (1024 * 1024)
    )]
    Unavailable {
        /// The estimate.
        estimate: MemoryEstimate,
        /// What the process can still allocate
        /// ([`fdm_run::memory::available_bytes`]), bytes.
        available_bytes: u64,
    },
}

impl MemoryEstimate {
    /// Refuses a study of `runs` runs that needs more than `limit_mib` MiB,
    /// or more than `available_bytes` (what the process can still allocate;
    /// `None`: not known, not checked).
    ///
    /// # Errors
    /// [`MemoryRefused`], with the numbers.
    pub fn check(
        self,
        runs: u64,
        limit_mib: u64,
        available_bytes: Option<u64>,
    ) -> Result<(), MemoryRefused> {
        if self.total > limit_mib.saturating_mul(1024 * 1024) {
            return Err(MemoryRefused::OverLimit {
                estimate: self,
                runs,
                limit_mib,
            });
        }
        match available_bytes {
            Some(available_bytes) if self.total > available_bytes => {
                Err(MemoryRefused::Unavailable {
                    estimate: self,
                    available_bytes,
                })
            }
            _ => Ok(()),
        }
    }
}
