//! The thin Entity-Component-System shell around `fdm-core` (thesis chapter III):
//! hecs components for aircraft parameters, state, controls and FlightGear
//! packets; the FlightControl → EquationsOfMotion → MakePacket → SendPacket
//! systems run in a fixed order; geodesy from the model's earth frame to WGS-84;
//! many aircraft of both models per world, stepped in parallel.

pub mod geodesy;
