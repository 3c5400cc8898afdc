//! Live data from a running PLC over OPC UA: `synth record` writes its inputs and outputs as a
//! CSV log, `synth monitor` runs a machine beside it and reports where the two part.
//!
//! In: the server's URL (`opc.tcp://HOST:PORT/PATH`), a mapping file of node ids
//! ([`Mapping`]: `ns=2;s=button in button`, the format of `synth ingest`'s mapping with an
//! OPC UA node id as the address) and, for the monitor, a machine. Out: rows of the CSV log
//! format ([`crate::scenario::csvlog`]) streamed to a file ([`record`]), and for the monitor
//! the divergences ([`monitor`]).
//!
//! # The protocol
//! The client is the `async-opcua` crate (OPC UA 1.05, binary `opc.tcp` transport); nothing
//! of the protocol is written here. [`client::Sampler`] connects as follows:
//! 1. **Endpoints**: GetEndpoints on the URL. With [`Security::Auto`] (the default) an
//!    endpoint with security policy `None` is taken when the server offers one (a lab server,
//!    a PLC on a closed cell network); otherwise `Basic256Sha256` with message mode
//!    `SignAndEncrypt` (then `Sign`). [`Security::None`] and [`Security::Basic256Sha256`]
//!    insist on one.
//! 2. **Certificates** (secure endpoints only): the client's application instance
//!    certificate and key live in the certificate folder (`--certs DIR`: `DIR/own/cert.der`,
//!    `DIR/private/private.pem`, made self-signed on first use). The server's certificate is
//!    trusted only when it is in `DIR/trusted/`; a refused one is put in `DIR/rejected/` by
//!    the client library, from where the user moves it to `DIR/trusted/` after checking its
//!    thumbprint, as with every OPC UA client.
//! 3. **Session**: CreateSession and ActivateSession with the anonymous identity; the
//!    session's event loop runs on a background task and renews the channel, keeps the
//!    session alive and reconnects after a lost connection (retrying every 0.5 to 2 s).
//! 4. **Sampling**: every interval (`--interval`, default 50 ms) one Read request of the
//!    Value attribute of every mapped node. One Read is one snapshot taken by the server at
//!    one instant, so a row never mixes two PLC scans, which per-item subscription
//!    notifications (queued and sent per publishing interval) could. Values must be Boolean
//!    (or an integer 0 or 1, as some PLCs publish bits); another value, or a bad status on a
//!    node (an unknown node id, say), stops the run with an error naming the node.
//! 5. **Gaps**: a Read that fails for the connection (closed, timed out, session lost) is a
//!    gap: no row is written for it, none is invented. The first row after a gap starts a new
//!    scenario (the `scenario` column of the log counts up), so readers take the stretches
//!    apart; the monitor stops at a gap, since the machine cannot follow the PLC across it.
//!
//! Timestamps are the client's, in seconds since the first row (monotonic clock, 3
//! decimals): the rows' order is the order of the Read responses.

pub(crate) mod client;
pub(crate) mod monitor;
pub(crate) mod record;

pub use crate::ingest::Mapping;
use std::path::PathBuf;
use std::time::Duration;

/// Which endpoint security the client asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Security {
    /// `None` when the server offers it, otherwise `Basic256Sha256`.
    #[default]
    Auto,
    /// No security (the server must offer the `None` policy).
    None,
    /// `Basic256Sha256`, signed and encrypted (or signed only when the server offers no more).
    Basic256Sha256,
}

/// How to reach the PLC.
#[derive(Debug, Clone)]
pub struct Connection {
    /// The server's endpoint URL, `opc.tcp://HOST:PORT[/PATH]`.
    pub url: String,
    /// The endpoint security asked for.
    pub security: Security,
    /// The certificate folder (PKI) of secure connections.
    pub certs: Option<PathBuf>,
    /// Time between two samples.
    pub interval: Duration,
}

/// When a live run stops (besides SIGINT, and the monitor's first divergence).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Until {
    /// After this many seconds from the start of sampling.
    Seconds(f64),
    /// After this many rows.
    Samples(u64),
    /// Only on a signal.
    Signal,
}

/// Counters of a live run, for the progress line.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Counters {
    /// Rows (samples) taken.
    pub rows: u64,
    /// Connection losses.
    pub gaps: u64,
    /// Scenarios written: 1, and one more for each gap between two rows.
    pub scenarios: u64,
    /// Monitor: steps compared.
    pub steps: u64,
    /// Seconds since the first row.
    pub seconds: f64,
}

/// Why a live run failed; each names the server's URL (and the node where one is at fault).
#[derive(Debug, thiserror::Error)]
pub enum LiveError {
    /// The URL is not an `opc.tcp://` URL.
    #[error("{url}: not an OPC UA endpoint URL (expected opc.tcp://HOST:PORT[/PATH])")]
    Url {
        /// The URL as given.
        url: String,
    },
    /// A mapping address that is not an OPC UA node id.
    #[error("{}:{line}: {address:?} is not an OPC UA node id (e.g. ns=2;s=button, ns=3;i=1001)", .file.display())]
    NodeId {
        /// The mapping file.
        file: PathBuf,
        /// Its line.
        line: usize,
        /// The address.
        address: String,
    },
    /// The client could not be set up (certificate folder, keys).
    #[error("{url}: cannot set up the OPC UA client: {message}")]
    Client {
        /// The server.
        url: String,
        /// What the client library said.
        message: String,
    },
    /// No connection: the server did not answer, refused the session or its certificate.
    #[error("{url}: cannot connect: {message}")]
    Connect {
        /// The server.
        url: String,
        /// Why.
        message: String,
    },
    /// The server offers no endpoint with the security asked for.
    #[error("{url}: {message}")]
    Endpoint {
        /// The server.
        url: String,
        /// What the server offers and what was asked.
        message: String,
    },
    /// A node that cannot be read, or whose value is not a bit.
    #[error("{url}: node {node} ({name}): {message}")]
    Node {
        /// The server.
        url: String,
        /// The node id, as the mapping gives it.
        node: String,
        /// The signal's name in the mapping.
        name: String,
        /// The status or the value.
        message: String,
    },
    /// The monitor lost the connection: the machine cannot follow the PLC across the gap.
    #[error("{url}: the connection was lost after {steps} compared steps (no divergence before it); the machine cannot follow the PLC across the gap: start the monitor again with the PLC")]
    Lost {
        /// The server.
        url: String,
        /// Steps compared before the gap.
        steps: u64,
    },
    /// The log or the divergent stretch could not be written.
    #[error(transparent)]
    Write(#[from] crate::files::WriteError),
    /// The machine's interface and the mapping's differ.
    #[error("{message}")]
    Interface {
        /// Which names differ.
        message: String,
    },
}
