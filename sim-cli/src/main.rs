//! `sim-cli`: fly Palmer's Cessna 172 or Bourg's 6-DoF aircraft (not implemented yet).

fn main() {
    eprintln!("sim-cli: not implemented yet");
    std::process::exit(1);
}
