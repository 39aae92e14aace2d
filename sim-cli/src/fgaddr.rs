//! `--fg HOST:PORT`: where FlightGear listens for native-FDM datagrams.

use std::fmt;
use std::net::{Ipv4Addr, SocketAddrV4, ToSocketAddrs};
use std::str::FromStr;

use crate::input::Echo;

/// Where interactive runs send packets when `--fg` is not given (docs/cli.md).
pub const DEFAULT_FG: &str = "127.0.0.1:5500";

/// A FlightGear native-FDM UDP endpoint as the user wrote it: a host name or IPv4
/// literal and a port. The host is kept as text because `fgfs-command` must print it
/// back exactly (`--native-fdm=socket,in,HZ,HOST,PORT,udp`), while the sender needs
/// the resolved address ([`FgTarget::resolve`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FgTarget {
    /// Host name or dotted IPv4 address (never empty).
    pub host: String,
    /// UDP port (never 0).
    pub port: u16,
}

impl Default for FgTarget {
    fn default() -> Self {
        Self {
            host: "127.0.0.1".to_owned(),
            port: 5500,
        }
    }
}

impl fmt::Display for FgTarget {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.host, self.port)
    }
}

/// Parses as [`parse_fg_listen`] (0.0.0.0 allowed); the send path refuses it in
/// [`parse_fg_target`] and again in [`FgTarget::resolve`].
impl FromStr for FgTarget {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        parse_fg_listen(s)
    }
}

/// Parses `--fg HOST:PORT` for sending: [`parse_host_port`], and the address must
/// be one host. The broadcast address (255.255.255.255: the kernel refuses it
/// without SO_BROADCAST, and FlightGear listens on one host anyway) and the
/// unspecified address (0.0.0.0: no host at all) are refused with the reason.
pub fn parse_fg_target(text: &str) -> Result<FgTarget, String> {
    let target = parse_host_port(text)?;
    if let Ok(ip) = target.host.parse::<Ipv4Addr>() {
        check_unicast(ip)?;
    }
    Ok(target)
}

/// Parses `fgfs-command --fg HOST:PORT`, the address FlightGear listens on:
/// [`parse_host_port`]; 0.0.0.0 (all interfaces) is allowed there, the
/// broadcast address is not.
pub fn parse_fg_listen(text: &str) -> Result<FgTarget, String> {
    let target = parse_host_port(text)?;
    if target
        .host
        .parse::<Ipv4Addr>()
        .is_ok_and(|ip| ip.is_broadcast())
    {
        return Err(format!(
            "`{}` is the broadcast address; FlightGear listens on one host's address (or 0.0.0.0 for all)",
            target.host
        ));
    }
    Ok(target)
}

/// Refuses the addresses a datagram cannot usefully be sent to.
fn check_unicast(ip: Ipv4Addr) -> Result<(), String> {
    if ip.is_broadcast() {
        return Err(format!(
            "`{ip}` is the broadcast address; give the address of the host FlightGear runs on (127.0.0.1 for this machine)"
        ));
    }
    if ip.is_unspecified() {
        return Err(format!(
            "`{ip}` is the unspecified address (no host); give the address of the host FlightGear runs on (127.0.0.1 for this machine)"
        ));
    }
    Ok(())
}

/// Parses `HOST:PORT` strictly. IPv6 is rejected up front because FlightGear
/// 2020.3's native-FDM socket is IPv4 only, so such a target could never work.
///
/// * HOST is a plain IPv4 dotted quad (four decimal numbers 0-255, no leading
///   zeros) or a host name: dot-separated labels of letters, digits and `-`
///   (1 to 63 characters, not starting or ending with `-`, 253 in all). A host
///   whose last label starts with a digit is taken as an IPv4 address and must be
///   a dotted quad, so the resolver never sees the old forms `0x7f.0.0.1`,
///   `127.1` or `2130706433`. This also keeps the printed fgfs command line safe
///   to paste into a shell.
/// * PORT is decimal digits only (no sign), 1 to 65535.
pub fn parse_host_port(text: &str) -> Result<FgTarget, String> {
    const FORMAT: &str = "expected HOST:PORT (e.g. 127.0.0.1:5500)";
    let shown = Echo::short(text);
    if text.starts_with('[') || text.matches(':').count() > 1 {
        return Err(format!(
            "`{shown}`: IPv6 is not supported (FlightGear's native-FDM socket is IPv4 only); {FORMAT}"
        ));
    }
    let Some((host, port)) = text.rsplit_once(':') else {
        return Err(format!("`{shown}`: missing port; {FORMAT}"));
    };
    if host.is_empty() {
        return Err(format!("`{shown}`: missing host; {FORMAT}"));
    }
    let last_label = host.rsplit('.').next().unwrap_or(host);
    if last_label.starts_with(|c: char| c.is_ascii_digit()) {
        if host.parse::<Ipv4Addr>().is_err() {
            return Err(format!(
                "`{}` is not a plain IPv4 address (four decimal numbers 0-255 separated by dots); {FORMAT}",
                Echo::short(host)
            ));
        }
    } else if !is_host_name(host) {
        return Err(format!(
            "`{}` is not a host name or IPv4 address; {FORMAT}",
            Echo::short(host)
        ));
    }
    let port = match port.parse::<u16>() {
        Ok(p) if p != 0 && port.bytes().all(|b| b.is_ascii_digit()) => p,
        _ => {
            return Err(format!(
                "port `{}` is not a decimal number in 1..65535; {FORMAT}",
                Echo::short(port)
            ))
        }
    };
    Ok(FgTarget {
        host: host.to_owned(),
        port,
    })
}

/// RFC 1123 host name syntax (letters, digits, hyphens; labels of 1-63).
fn is_host_name(host: &str) -> bool {
    host.len() <= 253
        && host.split('.').all(|label| {
            (1..=63).contains(&label.len())
                && label
                    .bytes()
                    .all(|b| b.is_ascii_alphanumeric() || b == b'-')
                && !label.starts_with('-')
                && !label.ends_with('-')
        })
}

impl FgTarget {
    /// Resolves the host to the first IPv4 address it names.
    ///
    /// # Errors
    /// A one-line message when the name does not resolve to any IPv4 address, or
    /// resolves to the broadcast or unspecified address (see [`parse_fg_target`]).
    pub fn resolve(&self) -> Result<SocketAddrV4, String> {
        let addrs = (self.host.as_str(), self.port)
            .to_socket_addrs()
            .map_err(|e| format!("cannot resolve FlightGear host `{}`: {e}", self.host))?;
        let addr = addrs
            .filter_map(|a| match a {
                std::net::SocketAddr::V4(v4) => Some(v4),
                std::net::SocketAddr::V6(_) => None,
            })
            .next()
            .ok_or_else(|| format!("FlightGear host `{}` has no IPv4 address", self.host))?;
        check_unicast(*addr.ip()).map_err(|e| format!("FlightGear host `{}`: {e}", self.host))?;
        Ok(addr)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_default_and_names() {
        assert_eq!(DEFAULT_FG.parse::<FgTarget>(), Ok(FgTarget::default()));
        let t = parse_fg_target("fg-box.local:5501").unwrap();
        assert_eq!((t.host.as_str(), t.port), ("fg-box.local", 5501));
        assert_eq!(t.to_string(), "fg-box.local:5501");
    }

    #[test]
    fn rejects_bad_formats() {
        for bad in [
            "",
            "5500",
            ":5500",
            "host:",
            "host:0",
            "host:65536",
            "host:port",
            "[::1]:5500",
            "::1:5500",
            "a b:1",
            "-x:1",
            "300.1.1.1:5500",
            "1.2.3:5500",
            "host;rm:1",
            "0x7f.0.0.1:5500",
            "127.1:5500",
            "2130706433:5500",
            "017.0.0.1:5500",
            "127.0.0.1:+5500",
            "127.0.0.1:0x15",
            "127.0.0.1: 5500",
            "a..b:5500",
            "a-.b:5500",
            "host.:5500",
            "255.255.255.255:5500",
            "0.0.0.0:5500",
        ] {
            let err = parse_fg_target(bad).expect_err(bad);
            assert!(!err.contains('\n'));
        }
    }

    #[test]
    fn broadcast_and_unspecified_are_refused_with_the_reason() {
        let err = parse_fg_target("255.255.255.255:5500").unwrap_err();
        assert!(err.contains("is the broadcast address"), "{err}");
        let err = parse_fg_target("0.0.0.0:5500").unwrap_err();
        assert!(err.contains("is the unspecified address"), "{err}");
        // FlightGear itself may listen on all interfaces.
        assert_eq!(parse_fg_listen("0.0.0.0:5500").unwrap().host, "0.0.0.0");
        assert!(parse_fg_listen("255.255.255.255:5500").is_err());
        let err = parse_fg_target("0x7f.0.0.1:+5500").unwrap_err();
        assert!(err.contains("not a plain IPv4 address"), "{err}");
        let err = parse_fg_target("127.0.0.1:+5500").unwrap_err();
        assert!(err.contains("not a decimal number"), "{err}");
    }

    #[test]
    fn resolves_ipv4_literal_without_dns() {
        let t = parse_fg_target("127.0.0.1:5500").unwrap();
        assert_eq!(
            t.resolve(),
            Ok(SocketAddrV4::new(Ipv4Addr::LOCALHOST, 5500))
        );
    }
}
