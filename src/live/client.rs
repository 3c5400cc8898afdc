//! The OPC UA client side: connect to a server (endpoint, security, session) and sample the
//! mapped nodes, one Read request per sample. The steps are in the [`super`] module header.
//!
//! In: a [`Connection`] and the mapping's node ids. Out: [`Reading`]s, a sample or a gap.
//! The library is asynchronous (tokio); [`Sampler`] keeps its own runtime (one worker thread,
//! where the session's event loop runs) so the rest of the crate stays synchronous.

use super::{Connection, LiveError, Security};
use crate::files::WorkDir;
use crate::ingest::{Mapping, Slot};
use crate::scenario::csvlog::Sample;
use opcua::client::{ClientBuilder, IdentityToken, Session};
use opcua::crypto::SecurityPolicy;
use opcua::types::{
    DataValue, EndpointDescription, MessageSecurityMode, NodeId, ReadValueId, StatusCode,
    TimestampsToReturn, UserTokenPolicy, Variant,
};
use std::path::Path;
use std::str::FromStr;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// How long the first connection may take before the run gives up.
const CONNECT_TIMEOUT: Duration = Duration::from_secs(10);

/// What one sampling tick brought.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Reading {
    /// The values of every mapped node, at `time` seconds since the first sample.
    Sample {
        /// Seconds since the first sample.
        time: f64,
        /// The values, in the mapping's interface order.
        sample: Sample,
    },
    /// The connection failed for this tick: nothing was read.
    Gap,
}

/// One mapped node: where its value goes, its id as written, and its name.
struct Node {
    slot: Slot,
    address: String,
    name: String,
}

/// A connected client that samples the mapped nodes at a fixed interval.
pub(crate) struct Sampler {
    runtime: tokio::runtime::Runtime,
    session: Arc<Session>,
    to_read: Vec<ReadValueId>,
    nodes: Vec<Node>,
    inputs: usize,
    outputs: usize,
    url: String,
    interval: Duration,
    next_tick: Instant,
    first: Option<Instant>,
    /// The certificate folder of a connection without security (the client library makes
    /// its folders there even when it uses no certificate), removed last: after the runtime,
    /// whose event loop may still read it.
    _own_pki: Option<WorkDir>,
}

/// The endpoint of `conn.url` to connect to, in the security `conn` asks for, with an
/// anonymous user.
async fn endpoint(
    client: &mut opcua::client::Client,
    conn: &Connection,
) -> Result<EndpointDescription, LiveError> {
    let url = &conn.url;
    let connect_err = |message: String| LiveError::Connect {
        url: url.clone(),
        message,
    };
    let endpoints = tokio::time::timeout(
        CONNECT_TIMEOUT,
        client.get_server_endpoints_from_url(url.as_str()),
    )
    .await
    .map_err(|_| connect_err("no answer to GetEndpoints".into()))?
    .map_err(|e| connect_err(e.to_string()))?;
    let secure_wanted = conn.security == Security::Basic256Sha256;
    let (policy, mode) =
        choose_endpoint(&endpoints, conn.security, secure_wanted).map_err(|message| {
            LiveError::Endpoint {
                url: url.clone(),
                message,
            }
        })?;
    if policy != SecurityPolicy::None && conn.certs.is_none() {
        return Err(LiveError::Endpoint {
            url: url.clone(),
            message: format!(
                "the server requires security ({policy}); give a certificate folder with --certs DIR"
            ),
        });
    }
    Ok((
        url.as_str(),
        policy.to_str(),
        mode,
        UserTokenPolicy::anonymous(),
    )
        .into())
}

/// A session on `endpoint`, its event loop started, once the server accepted it.
async fn session(
    client: &mut opcua::client::Client,
    endpoint: EndpointDescription,
    url: &str,
) -> Result<Arc<Session>, LiveError> {
    let connect_err = |message: String| LiveError::Connect {
        url: url.to_string(),
        message,
    };
    let (session, event_loop) = client
        .connect_to_matching_endpoint(endpoint, IdentityToken::Anonymous)
        .await
        .map_err(|e| connect_err(e.to_string()))?;
    event_loop.spawn();
    match tokio::time::timeout(CONNECT_TIMEOUT, session.wait_for_connection()).await {
        Ok(true) => Ok(session),
        Ok(false) => Err(connect_err(
            "the server refused the session (with security: is its certificate in DIR/trusted/, and ours trusted by it?)".into(),
        )),
        Err(_) => Err(connect_err(format!(
            "no session within {} s",
            CONNECT_TIMEOUT.as_secs()
        ))),
    }
}

/// The node id of every mapped signal, in the mapping's address order; a bad one names the
/// mapping file and line.
pub(crate) fn node_ids(mapping: &Mapping, file: &Path) -> Result<Vec<NodeId>, LiveError> {
    (mapping.addresses().iter().enumerate())
        .map(|(k, (address, _))| {
            NodeId::from_str(address).map_err(|_| LiveError::NodeId {
                file: file.to_path_buf(),
                line: mapping.line(k),
                address: address.clone(),
            })
        })
        .collect()
}

/// Whether a Read failed for the connection (a gap) rather than for the request.
fn is_connection_status(status: StatusCode) -> bool {
    [
        StatusCode::BadNotConnected,
        StatusCode::BadConnectionClosed,
        StatusCode::BadTimeout,
        StatusCode::BadSessionClosed,
        StatusCode::BadSessionIdInvalid,
        StatusCode::BadSecureChannelClosed,
        StatusCode::BadSecureChannelIdInvalid,
        StatusCode::BadCommunicationError,
        StatusCode::BadServerNotConnected,
        StatusCode::BadServerHalted,
        StatusCode::BadShutdown,
        StatusCode::BadRequestTimeout,
        StatusCode::BadTooManyOperations,
        StatusCode::BadInvalidState,
    ]
    .contains(&status)
}

/// Whether a Read failed because the server does not know the session (yet): it restarted,
/// and the client library is making a new one.
fn is_session_coming_back(status: StatusCode) -> bool {
    [
        StatusCode::BadUserAccessDenied,
        StatusCode::BadSessionNotActivated,
    ]
    .contains(&status)
}

impl Sampler {
    /// Connects to `conn.url` and checks that every node of `mapping` (ids in `ids`) reads as
    /// a bit.
    pub(crate) fn connect(
        conn: &Connection,
        mapping: &Mapping,
        ids: Vec<NodeId>,
    ) -> Result<Sampler, LiveError> {
        let url = conn.url.clone();
        if !url.starts_with("opc.tcp://") {
            return Err(LiveError::Url { url });
        }
        let client_err = |message: String| LiveError::Client {
            url: url.clone(),
            message,
        };
        // One worker: the session's event loop (keep-alive, reconnects) runs between reads.
        let runtime = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(1)
            .thread_name("opcua")
            .enable_all()
            .build()
            .map_err(|e| client_err(e.to_string()))?;
        let (pki, own_pki) = match &conn.certs {
            Some(dir) => (dir.clone(), None),
            None => {
                let own = WorkDir::new().map_err(|e| client_err(e.to_string()))?;
                (own.path().to_path_buf(), Some(own))
            }
        };
        let mut client = ClientBuilder::new()
            .application_name("fbsynth synth")
            .application_uri("urn:fbsynth:synth")
            .product_uri("urn:fbsynth")
            .pki_dir(pki)
            .create_sample_keypair(conn.certs.is_some())
            .trust_server_certs(false)
            .session_retry_limit(-1)
            .session_retry_initial(Duration::from_millis(500))
            .session_retry_max(Duration::from_secs(2))
            .request_timeout(Duration::from_secs(2))
            .session_timeout(30_000)
            .client()
            .map_err(|errors| client_err(errors.join("; ")))?;
        let endpoint = runtime.block_on(endpoint(&mut client, conn))?;
        let session = runtime.block_on(session(&mut client, endpoint, &url))?;
        let nodes = (mapping.addresses().iter())
            .map(|(address, slot)| Node {
                slot: *slot,
                address: address.clone(),
                name: match slot {
                    Slot::Input(x) => mapping.inputs()[x.0].clone(),
                    Slot::Output(z) => mapping.outputs()[z.0].clone(),
                },
            })
            .collect();
        Ok(Sampler {
            runtime,
            session,
            to_read: ids.into_iter().map(ReadValueId::from).collect(),
            nodes,
            inputs: mapping.inputs().len(),
            outputs: mapping.outputs().len(),
            url,
            interval: conn.interval,
            next_tick: Instant::now(),
            first: None,
            _own_pki: own_pki,
        })
    }

    /// Waits for the next tick and reads every node once.
    pub(crate) fn next(&mut self) -> Result<Reading, LiveError> {
        let now = Instant::now();
        if self.next_tick > now {
            std::thread::sleep(self.next_tick - now);
        }
        // A late tick is not caught up with a burst of reads: the next one is an interval on.
        self.next_tick = (self.next_tick + self.interval).max(Instant::now());
        let wait = Duration::from_secs(2).max(2 * self.interval);
        let session = self.session.clone();
        let to_read = self.to_read.clone();
        let read = self.runtime.block_on(async move {
            tokio::time::timeout(
                wait,
                session.read(&to_read, TimestampsToReturn::Neither, 0.0),
            )
            .await
        });
        let values = match read {
            Err(_) => return Ok(Reading::Gap),
            Ok(Err(status)) if is_connection_status(status) => return Ok(Reading::Gap),
            // A server restarted under a running session refuses its reads until the client
            // library has made and activated a new session: the connection is still coming
            // back. Before the first reading the same answer is the server's refusal.
            Ok(Err(status)) if self.first.is_some() && is_session_coming_back(status) => {
                return Ok(Reading::Gap)
            }
            Ok(Err(status)) => {
                return Err(LiveError::Connect {
                    url: self.url.clone(),
                    message: format!("Read failed: {status}"),
                })
            }
            Ok(Ok(values)) => values,
        };
        let sample = self.sample(&values)?;
        let first = *self.first.get_or_insert_with(Instant::now);
        Ok(Reading::Sample {
            time: first.elapsed().as_secs_f64(),
            sample,
        })
    }

    /// The sample in `values`, one per node in the mapping's address order.
    fn sample(&self, values: &[DataValue]) -> Result<Sample, LiveError> {
        let mut sample = Sample {
            inputs: vec![false; self.inputs],
            outputs: vec![false; self.outputs],
        };
        if values.len() != self.nodes.len() {
            return Err(LiveError::Connect {
                url: self.url.clone(),
                message: format!(
                    "Read answered {} values for {} nodes",
                    values.len(),
                    self.nodes.len()
                ),
            });
        }
        for (node, value) in self.nodes.iter().zip(values) {
            let bit = bit(value).map_err(|message| LiveError::Node {
                url: self.url.clone(),
                node: node.address.clone(),
                name: node.name.clone(),
                message,
            })?;
            match node.slot {
                Slot::Input(x) => sample.inputs[x.0] = bit,
                Slot::Output(z) => sample.outputs[z.0] = bit,
            }
        }
        Ok(sample)
    }

    /// The server's URL.
    pub(crate) fn url(&self) -> &str {
        &self.url
    }

    /// Closes the session (best effort: the run's result does not depend on it).
    pub(crate) fn close(self) {
        let session = self.session;
        let _ = self.runtime.block_on(async move {
            tokio::time::timeout(Duration::from_secs(2), session.disconnect()).await
        });
    }
}

/// A node's value as a bit: a Boolean, or an integer 0 or 1.
fn bit(value: &DataValue) -> Result<bool, String> {
    if let Some(status) = value.status {
        if !status.is_good() {
            return Err(format!("status {status}"));
        }
    }
    let integer = |v: i128| match v {
        0 => Ok(false),
        1 => Ok(true),
        _ => Err(format!("value {v} is not a bit (Boolean, or 0 or 1)")),
    };
    match &value.value {
        Some(Variant::Boolean(b)) => Ok(*b),
        Some(Variant::SByte(v)) => integer(*v as i128),
        Some(Variant::Byte(v)) => integer(*v as i128),
        Some(Variant::Int16(v)) => integer(*v as i128),
        Some(Variant::UInt16(v)) => integer(*v as i128),
        Some(Variant::Int32(v)) => integer(*v as i128),
        Some(Variant::UInt32(v)) => integer(*v as i128),
        Some(Variant::Int64(v)) => integer(*v as i128),
        Some(Variant::UInt64(v)) => integer(*v as i128),
        Some(other) => Err(format!("value {other:?} is not a bit (Boolean, or 0 or 1)")),
        None => Err("no value".into()),
    }
}

/// The security policy and mode of the endpoint to use, from what the server offers.
fn choose_endpoint(
    endpoints: &[EndpointDescription],
    security: Security,
    secure_wanted: bool,
) -> Result<(SecurityPolicy, MessageSecurityMode), String> {
    let offers = |policy: SecurityPolicy, mode: MessageSecurityMode| {
        endpoints.iter().any(|e| {
            e.security_mode == mode
                && SecurityPolicy::from_str(e.security_policy_uri.as_ref()).ok() == Some(policy)
        })
    };
    if !secure_wanted && offers(SecurityPolicy::None, MessageSecurityMode::None) {
        return Ok((SecurityPolicy::None, MessageSecurityMode::None));
    }
    if security != Security::None {
        for mode in [
            MessageSecurityMode::SignAndEncrypt,
            MessageSecurityMode::Sign,
        ] {
            if offers(SecurityPolicy::Basic256Sha256, mode) {
                return Ok((SecurityPolicy::Basic256Sha256, mode));
            }
        }
    }
    let offered: Vec<String> = endpoints
        .iter()
        .map(|e| format!("{} {:?}", e.security_policy_uri, e.security_mode))
        .collect();
    let asked = match security {
        Security::None => "security None",
        Security::Basic256Sha256 => "Basic256Sha256",
        Security::Auto => "security None or Basic256Sha256",
    };
    Err(format!(
        "the server offers no endpoint with {asked}; it offers: {}",
        offered.join(", ")
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bits_are_booleans_or_zero_and_one() {
        let dv = |v: Variant| DataValue::new_now(v);
        assert_eq!(bit(&dv(Variant::Boolean(true))), Ok(true));
        assert_eq!(bit(&dv(Variant::Byte(0))), Ok(false));
        assert_eq!(bit(&dv(Variant::Int32(1))), Ok(true));
        assert!(bit(&dv(Variant::Int32(2)))
            .unwrap_err()
            .contains("not a bit"));
        assert!(bit(&dv(Variant::Double(1.0))).is_err());
    }

    #[test]
    fn bad_node_ids_name_the_mapping_line() {
        let path = Path::new("plc.map");
        let m = Mapping::parse(path, "ns=2;s=start in start\n\nbogus out motor\n").unwrap();
        let e = node_ids(&m, path).unwrap_err().to_string();
        assert!(
            e.starts_with("plc.map:3: \"bogus\" is not an OPC UA node id"),
            "{e}"
        );
        let m = Mapping::parse(path, "ns=2;s=start in start\nns=3;i=1001 out motor\n").unwrap();
        assert_eq!(node_ids(&m, path).unwrap().len(), 2);
    }
}
