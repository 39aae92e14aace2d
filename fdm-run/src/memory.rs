//! How much memory this process can still allocate: the least of the
//! machine's available memory, the address-space limit (`RLIMIT_AS`, what
//! `ulimit -v` sets) less the address space already in use, and the memory
//! limit of the process's cgroup less what the cgroup already uses
//! ([`available_bytes`]). A fleet run refuses a fleet that does not fit in
//! it ([`check_fleet`], [`MemoryRefused`]) instead of letting its
//! allocations abort the process; [`estimated_bytes_per_aircraft`] and
//! [`resident_bytes`] give the figures its report carries.

use fdm_core::model::{FlightStatus, Model};
use fdm_ecs::components::{FrameInput, Params};

/// Bytes one flying-only aircraft of model `M` takes in an ECS world: its
/// components (parameters handle, controls, state, input queue, status) plus
/// hecs's per-entity bookkeeping (the entity id in the archetype and the
/// entity table, measured at about 16 bytes). The estimate the memory check
/// of an ECS fleet uses; the fleet report gives the measured figure beside it.
#[must_use]
pub fn estimated_bytes_per_aircraft<M: Model>() -> u64 {
    let components = std::mem::size_of::<Params<M>>()
        + std::mem::size_of::<M::Controls>()
        + std::mem::size_of::<M::State>()
        + std::mem::size_of::<FrameInput<M::Action>>()
        + std::mem::size_of::<FlightStatus>();
    (components + 16) as u64
}

/// This process's resident memory in bytes (`/proc/self/statm`); `None` where
/// that is not known.
#[must_use]
pub fn resident_bytes() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/self/statm").ok()?;
    let pages: u64 = text.split_whitespace().nth(1)?.parse().ok()?;
    // Linux pages are 4 KiB on the machines this runs on (x86-64, aarch64 default).
    pages.checked_mul(4096)
}

/// A fleet refused because it does not fit in the memory this process can
/// still allocate ([`check_fleet`]).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "a fleet of {aircraft} {model} aircraft needs about {} MiB ({per_aircraft_bytes} bytes each, \
     twice that while the fleet grows); this process has {} MiB available{}",
    needed_bytes / (1024 * 1024),
    available_bytes / (1024 * 1024),
    if *allocator_refused { ", but the allocator refuses that much" } else { "" }
)]
pub struct MemoryRefused {
    /// The model's name ([`Model::NAME`]).
    pub model: &'static str,
    /// Aircraft in the fleet.
    pub aircraft: u64,
    /// Bytes per aircraft (the estimate).
    pub per_aircraft_bytes: u64,
    /// Bytes the fleet needs: twice `aircraft × per_aircraft_bytes` (the
    /// arrays double as they grow).
    pub needed_bytes: u64,
    /// Bytes this process can still allocate ([`available_bytes`]).
    pub available_bytes: u64,
    /// The estimate fits in `available_bytes`, but reserving that much
    /// address space failed.
    pub allocator_refused: bool,
}

/// Refuses a fleet of `aircraft` aircraft of `model` at `per_aircraft_bytes`
/// each when twice that (hecs doubles an archetype's columns as it fills, a
/// kernel's arrays double as they grow, so up to twice the live size is
/// allocated for a moment) exceeds `available_bytes`, or when the allocator
/// will not grant that much address space. `None` available: nothing to
/// check against.
///
/// # Errors
/// [`MemoryRefused`], saying how much the fleet needs and the process has.
pub fn check_fleet(
    model: &'static str,
    aircraft: u64,
    per_aircraft_bytes: u64,
    available_bytes: Option<u64>,
) -> Result<(), MemoryRefused> {
    let needed_bytes = aircraft
        .saturating_mul(per_aircraft_bytes)
        .saturating_mul(2);
    let refuse = |have: u64, allocator_refused: bool| MemoryRefused {
        model,
        aircraft,
        per_aircraft_bytes,
        needed_bytes,
        available_bytes: have,
        allocator_refused,
    };
    match available_bytes {
        Some(have) if needed_bytes > have => Err(refuse(have, false)),
        // The estimate fits: the allocator must also grant that much address
        // space (tried, never touched), or the fleet's own allocations would
        // abort the process instead of this refusal.
        Some(have) if !can_reserve(needed_bytes) => Err(refuse(have, true)),
        _ => Ok(()),
    }
}

/// Bytes this process can still allocate: the least of the limits that are
/// known ([`machine_available`], [`address_space_left`], [`cgroup_left`]);
/// `None` when none is.
#[must_use]
pub fn available_bytes() -> Option<u64> {
    [machine_available(), address_space_left(), cgroup_left()]
        .into_iter()
        .flatten()
        .min()
}

/// Bytes of memory the system says can still be allocated without swapping
/// (`MemAvailable` of `/proc/meminfo`); `None` where that is not known.
#[must_use]
pub fn machine_available() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    meminfo_available(&text)
}

fn meminfo_available(text: &str) -> Option<u64> {
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}

/// The address-space limit (`RLIMIT_AS`'s soft limit) less the address space
/// this process already maps (`VmSize`); `None` without a limit or where it
/// is not known.
#[must_use]
pub fn address_space_left() -> Option<u64> {
    let limit = address_space_limit()?;
    let used = std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|status| status_vm_size(&status))
        .unwrap_or(0);
    Some(limit.saturating_sub(used))
}

/// `RLIMIT_AS`'s soft limit (`None`: unlimited, or not a unix system). One
/// function with the platforms inside: a body per platform would make
/// mutants the other platform cannot build.
fn address_space_limit() -> Option<u64> {
    #[cfg(unix)]
    {
        rustix::process::getrlimit(rustix::process::Resource::As).current
    }
    #[cfg(not(unix))]
    {
        None
    }
}

/// `VmSize` of `/proc/self/status`, bytes.
fn status_vm_size(status: &str) -> Option<u64> {
    let line = status.lines().find(|l| l.starts_with("VmSize:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}

/// The memory limit of this process's cgroup less its current use: cgroup v2
/// (`memory.max` and `memory.current`) or v1 (`memory.limit_in_bytes` and
/// `memory.usage_in_bytes`); `None` without a limit (`max`) or where it is not
/// known.
#[must_use]
pub fn cgroup_left() -> Option<u64> {
    let cgroups = std::fs::read_to_string("/proc/self/cgroup").ok()?;
    cgroup_left_in(&cgroups, |path| std::fs::read_to_string(path).ok())
}

/// [`cgroup_left`] for `cgroups`, the text of `/proc/self/cgroup`, reading
/// the cgroup's files through `read` (a path under `/sys/fs/cgroup`).
fn cgroup_left_in(cgroups: &str, read: impl Fn(String) -> Option<String>) -> Option<u64> {
    for line in cgroups.lines() {
        let mut fields = line.splitn(3, ':');
        let (_, controllers, path) = (fields.next()?, fields.next()?, fields.next()?);
        let path = path.trim_end();
        let left = if controllers.is_empty() {
            let dir = format!("/sys/fs/cgroup{path}");
            cgroup_room(
                read(format!("{dir}/memory.max")).as_deref(),
                read(format!("{dir}/memory.current")).as_deref(),
            )
        } else if controllers.split(',').any(|c| c == "memory") {
            let dir = format!("/sys/fs/cgroup/memory{path}");
            cgroup_room(
                read(format!("{dir}/memory.limit_in_bytes")).as_deref(),
                read(format!("{dir}/memory.usage_in_bytes")).as_deref(),
            )
        } else {
            None
        };
        if left.is_some() {
            return left;
        }
    }
    None
}

/// A cgroup's limit less its use, from the files' text; `None` for no limit
/// (`max`, or v1's near-`u64::MAX` "unlimited") or unreadable text.
fn cgroup_room(limit: Option<&str>, current: Option<&str>) -> Option<u64> {
    let limit: u64 = limit?.trim().parse().ok()?;
    // cgroup v1 writes "no limit" as the largest page-aligned i64.
    if limit >= (i64::MAX as u64) & !0xfff {
        return None;
    }
    let current = current
        .and_then(|c| c.trim().parse::<u64>().ok())
        .unwrap_or(0);
    Some(limit.saturating_sub(current))
}

/// Reserves (without touching) `bytes` of address space and gives it back:
/// `false` when the allocator refuses them, as under an address-space limit.
/// A probe before allocations that would otherwise abort the process.
#[must_use]
pub fn can_reserve(bytes: u64) -> bool {
    let Ok(bytes) = usize::try_from(bytes) else {
        return false;
    };
    let mut probe: Vec<u8> = Vec::new();
    probe.try_reserve_exact(bytes).is_ok()
}

#[cfg(test)]
mod tests {
    use super::*;
    use fdm_core::palmer::Palmer;

    #[test]
    fn fleets_that_do_not_fit_are_refused_saying_how_much() {
        let gib = 1024 * 1024 * 1024;
        let per = estimated_bytes_per_aircraft::<Palmer>();
        let err = check_fleet(Palmer::NAME, 10_000_000, per, Some(gib)).unwrap_err();
        assert!(!err.allocator_refused);
        let message = err.to_string();
        let need_mib = 10_000_000 * per * 2 / (1024 * 1024);
        assert!(
            message.contains(&format!("needs about {need_mib} MiB"))
                && message.contains("has 1024 MiB available"),
            "{message}"
        );
        assert!(check_fleet(Palmer::NAME, 1_000, per, Some(gib)).is_ok());
        // Unknown available memory: nothing to check against.
        assert!(check_fleet(Palmer::NAME, 10_000_000, per, None).is_ok());
        // A lean entity: a few dozen bytes of state and controls, well under
        // the kilobyte a full aircraft with its datagram takes.
        assert!((100..200).contains(&per), "{per}");
    }

    /// The estimate is what its documentation adds up: the five components
    /// and 16 bytes of hecs's bookkeeping.
    #[test]
    fn the_estimate_is_the_components_and_the_bookkeeping() {
        use std::mem::size_of;
        type P = Palmer;
        let components = size_of::<Params<P>>()
            + size_of::<<P as Model>::Controls>()
            + size_of::<<P as Model>::State>()
            + size_of::<FrameInput<<P as Model>::Action>>()
            + size_of::<FlightStatus>();
        assert_eq!(estimated_bytes_per_aircraft::<P>(), components as u64 + 16);
    }

    /// A fleet whose doubled size is exactly what is available fits; one
    /// whose estimate fits but whose address space the allocator will not
    /// reserve is refused, saying so.
    #[test]
    fn the_limit_is_inclusive_and_the_allocator_has_the_last_word() {
        assert_eq!(check_fleet(Palmer::NAME, 1_000, 100, Some(200_000)), Ok(()));
        assert!(check_fleet(Palmer::NAME, 1_000, 100, Some(199_999)).is_err());
        // 2^61 bytes: below the u64 "available", beyond any address space.
        let err = check_fleet(Palmer::NAME, 1 << 40, 1 << 20, Some(u64::MAX)).unwrap_err();
        assert!(err.allocator_refused);
        assert_eq!(err.needed_bytes, 1 << 61);
        assert!(
            err.to_string()
                .ends_with(", but the allocator refuses that much"),
            "{err}"
        );
    }

    /// This process's resident memory is `/proc/self/status`'s `VmRSS`
    /// (in pages rather than kB): within a factor of two of it, read a
    /// moment apart while other tests run, and above a megabyte.
    #[cfg(target_os = "linux")]
    #[test]
    fn resident_memory_is_the_processs() {
        let resident = resident_bytes().expect("Linux has /proc/self/statm");
        let status = std::fs::read_to_string("/proc/self/status").unwrap();
        let line = status.lines().find(|l| l.starts_with("VmRSS:")).unwrap();
        let rss: u64 = line.split_whitespace().nth(1).unwrap().parse().unwrap();
        let rss = rss * 1024;
        assert!(resident > 1 << 20, "{resident}");
        assert!(
            resident / 2 <= rss && rss <= resident * 2,
            "{resident} {rss}"
        );
    }

    /// The address-space limit is the soft limit `/proc/self/limits`
    /// shows ("unlimited": none).
    #[cfg(target_os = "linux")]
    #[test]
    fn the_address_space_limit_is_the_soft_rlimit() {
        let limits = std::fs::read_to_string("/proc/self/limits").unwrap();
        let line = limits
            .lines()
            .find(|l| l.starts_with("Max address space"))
            .unwrap();
        let soft = line["Max address space".len()..]
            .split_whitespace()
            .next()
            .unwrap();
        let want = (soft != "unlimited").then(|| soft.parse::<u64>().unwrap());
        assert_eq!(address_space_limit(), want, "{line}");
        assert_eq!(address_space_left().is_some(), want.is_some());
    }

    /// The cgroup's room is read where `/proc/self/cgroup` says: v2's
    /// `memory.max` and `memory.current` for the unified line (`0::PATH`),
    /// v1's `memory.limit_in_bytes` and `memory.usage_in_bytes` under the
    /// memory controller's line (alone or among others), no other
    /// controller's; the first line with a limit answers.
    #[test]
    fn the_cgroup_is_found_from_proc_self_cgroup() {
        let files = |pairs: &'static [(&'static str, &'static str)]| {
            move |path: String| {
                pairs
                    .iter()
                    .find(|(p, _)| *p == path)
                    .map(|(_, text)| (*text).to_owned())
            }
        };
        let v2 = files(&[
            ("/sys/fs/cgroup/user.slice/a/memory.max", "4096\n"),
            ("/sys/fs/cgroup/user.slice/a/memory.current", "1000\n"),
        ]);
        assert_eq!(cgroup_left_in("0::/user.slice/a\n", v2), Some(3096));
        let v1 = files(&[
            (
                "/sys/fs/cgroup/memory/docker/b/memory.limit_in_bytes",
                "8192\n",
            ),
            (
                "/sys/fs/cgroup/memory/docker/b/memory.usage_in_bytes",
                "192\n",
            ),
            ("/sys/fs/cgroup/cpu/docker/b/memory.limit_in_bytes", "1\n"),
        ]);
        let v1_lines = "3:cpu,cpuacct:/docker/b\n4:memory:/docker/b\n0::/\n";
        assert_eq!(cgroup_left_in(v1_lines, v1), Some(8000));
        assert_eq!(cgroup_left_in("4:blkio,memory:/docker/b\n", v1), Some(8000));
        // Another controller's line is not the memory cgroup's.
        assert_eq!(cgroup_left_in("3:cpu,cpuacct:/docker/b\n", v1), None);
        // No limit anywhere, or no cgroup file: nothing known.
        let unlimited = files(&[
            ("/sys/fs/cgroup/memory.max", "max\n"),
            ("/sys/fs/cgroup/memory.current", "5\n"),
        ]);
        assert_eq!(cgroup_left_in("0::/\n", unlimited), None);
        assert_eq!(cgroup_left_in("0::/gone\n", unlimited), None);
    }

    /// Under an address-space limit (`ulimit -v` in a child process: the
    /// limit is the process's), the limit is known, what is left of it is
    /// less than it and more than nothing, and nothing is said to be
    /// available beyond it.
    #[cfg(target_os = "linux")]
    #[test]
    fn an_address_space_limit_bounds_what_is_available() {
        const LIMIT_KIB: u64 = 64 * 1024 * 1024; // 64 GiB
        const NAME: &str = "memory::tests::an_address_space_limit_bounds_what_is_available";
        if std::env::var_os("FDM_RUN_MEMORY_CHILD").is_some() {
            assert_eq!(address_space_limit(), Some(LIMIT_KIB * 1024));
            let left = address_space_left().unwrap();
            assert!(0 < left && left < LIMIT_KIB * 1024, "{left}");
            assert!(available_bytes().is_some_and(|a| a <= left));
            return;
        }
        let exe = std::env::current_exe().unwrap();
        let out = std::process::Command::new("sh")
            .arg("-c")
            .arg(format!(
                "ulimit -v {LIMIT_KIB} && exec \"$0\" --exact {NAME} --test-threads 1"
            ))
            .arg(exe)
            .env("FDM_RUN_MEMORY_CHILD", "1")
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(
            out.status.success() && stdout.contains("1 passed"),
            "{stdout}{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }

    #[test]
    fn meminfo_and_status_are_read_in_bytes() {
        let meminfo = "MemTotal:  100 kB\nMemFree: 5 kB\nMemAvailable:    2048 kB\n";
        assert_eq!(meminfo_available(meminfo), Some(2048 * 1024));
        assert_eq!(meminfo_available("MemTotal: 1 kB\n"), None);
        let status = "Name:\tsim-cli\nVmPeak:\t  9000 kB\nVmSize:\t  8000 kB\n";
        assert_eq!(status_vm_size(status), Some(8000 * 1024));
    }

    #[test]
    fn cgroup_limits_less_use_and_no_limit() {
        assert_eq!(cgroup_room(Some("1000\n"), Some("300\n")), Some(700));
        assert_eq!(cgroup_room(Some("100\n"), Some("300\n")), Some(0));
        assert_eq!(cgroup_room(Some("max\n"), Some("300\n")), None);
        assert_eq!(
            cgroup_room(Some("9223372036854771712\n"), Some("300\n")),
            None
        );
        assert_eq!(cgroup_room(None, Some("300")), None);
    }

    #[test]
    fn the_least_known_limit_is_available() {
        let all = available_bytes();
        for one in [machine_available(), address_space_left(), cgroup_left()]
            .into_iter()
            .flatten()
        {
            assert!(all.is_some_and(|a| a <= one));
        }
    }

    #[test]
    fn impossible_reservations_are_refused_not_aborted() {
        assert!(!can_reserve(u64::MAX));
        assert!(can_reserve(1024));
    }
}
