//! `--fg HOST:PORT`: where FlightGear listens for native-FDM datagrams.

use std::fmt;
use std::net::{Ipv4Addr, SocketAddrV4, ToSocketAddrs};
use std::str::FromStr;

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

impl FromStr for FgTarget {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        parse_fg_target(s)
    }
}

/// Parses `HOST:PORT`. IPv6 is rejected up front because FlightGear 2020.3's
/// native-FDM socket is IPv4 only (docs/fgnetfdm.md §5), so such a target could never work.
/// Host names are limited to letters, digits, `.` and `-`, which also keeps the
/// printed fgfs command line safe to paste into a shell.
pub fn parse_fg_target(text: &str) -> Result<FgTarget, String> {
    const FORMAT: &str = "expected HOST:PORT (e.g. 127.0.0.1:5500)";
    if text.starts_with('[') || text.matches(':').count() > 1 {
        return Err(format!(
            "`{text}`: IPv6 is not supported (FlightGear's native-FDM socket is IPv4 only); {FORMAT}"
        ));
    }
    let Some((host, port)) = text.rsplit_once(':') else {
        return Err(format!("`{text}`: missing port; {FORMAT}"));
    };
    if host.is_empty() {
        return Err(format!("`{text}`: missing host; {FORMAT}"));
    }
    let valid_host = host
        .bytes()
        .all(|b| b.is_ascii_alphanumeric() || b == b'.' || b == b'-')
        && !host.starts_with(['-', '.']);
    if !valid_host {
        return Err(format!(
            "`{host}` is not a host name or IPv4 address; {FORMAT}"
        ));
    }
    // A host that looks numeric must be a real IPv4 literal: "300.1.2.3" or "1.2.3"
    // would otherwise go to the resolver and fail later with a vaguer message.
    if host.bytes().all(|b| b.is_ascii_digit() || b == b'.') && host.parse::<Ipv4Addr>().is_err() {
        return Err(format!("`{host}` is not a valid IPv4 address; {FORMAT}"));
    }
    let port = match port.parse::<u16>() {
        Ok(0) | Err(_) => return Err(format!("port `{port}` is not in 1..65535; {FORMAT}")),
        Ok(p) => p,
    };
    Ok(FgTarget {
        host: host.to_owned(),
        port,
    })
}

impl FgTarget {
    /// Resolves the host to the first IPv4 address it names.
    ///
    /// # Errors
    /// A one-line message when the name does not resolve to any IPv4 address.
    pub fn resolve(&self) -> Result<SocketAddrV4, String> {
        let addrs = (self.host.as_str(), self.port)
            .to_socket_addrs()
            .map_err(|e| format!("cannot resolve FlightGear host `{}`: {e}", self.host))?;
        addrs
            .filter_map(|a| match a {
                std::net::SocketAddr::V4(v4) => Some(v4),
                std::net::SocketAddr::V6(_) => None,
            })
            .next()
            .ok_or_else(|| format!("FlightGear host `{}` has no IPv4 address", self.host))
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
        ] {
            let err = parse_fg_target(bad).expect_err(bad);
            assert!(!err.contains('\n'));
        }
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
