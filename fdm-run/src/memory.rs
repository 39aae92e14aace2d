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

#[cfg(unix)]
fn address_space_limit() -> Option<u64> {
    rustix::process::getrlimit(rustix::process::Resource::As).current
}

#[cfg(not(unix))]
fn address_space_limit() -> Option<u64> {
    None
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
    let read = |path: String| std::fs::read_to_string(path).ok();
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
