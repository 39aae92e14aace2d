//! Empty: this package exists for its tests (`tests/`), which run
//! fdm-core built without `std` on the host. See `Cargo.toml`.
#![no_std]
