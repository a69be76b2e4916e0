//! A CNC's axes from its OPC UA server (async-opcua's client): the OPC 40502 CNC model found by
//! browsing (`Objects/CncInterface/CncAxisList`, each axis' `PosIndirect` or `PosDirect` `ActPos`,
//! its `EngineeringUnits` and `IsRotational`), subscribed to at the sampling interval asked, each
//! value taken at its SourceTimestamp. A lost connection is made again from the start: the model
//! browsed anew (a restarted server may number its nodes otherwise) and the subscription created
//! again, so the stream goes on as before.

use fiveaxis::machine::{AxisKind, Machine};
use fiveaxis::opcua::{self as model, Measuring, Security};
use fiveaxis::source::{ByInstant, Event, Failure, KeepGoing, Retry, Stamp};
use opcua::client::{ClientBuilder, DataChangeCallback, IdentityToken, MonitoredItem, Session};
use opcua::crypto::SecurityPolicy;
use opcua::types::{
    AttributeId, BrowseDescription, BrowseDirection, BrowsePath, DataValue, EUInformation, MessageSecurityMode, MonitoredItemCreateRequest, NodeClass, NodeId, QualifiedName,
    ReadValueId, ReferenceTypeId, RelativePath, RelativePathElement, TimestampsToReturn, UserTokenPolicy, Variant,
};
use std::collections::BTreeMap;
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// An OPC UA server to read a machine's axes from.
pub struct OpcUa {
    pub url: String,
    pub measuring: Measuring,
    pub sampling: Duration,
    /// Machine axis -> the CncAxis browse name where they differ.
    pub axis_map: BTreeMap<String, String>,
    pub assume_mm_deg: bool,
    /// A node per machine axis, for a control's own address space (a Sinumerik's
    /// `ns=2;s=/Channel/MachineAxis/actToolBasePos[u1,1]`): no CNC model is browsed then.
    pub nodes: BTreeMap<String, NodeId>,
    /// The channel's security and the user's identity (anonymous without one).
    pub security: Security,
    pub identity: Option<(String, String)>,
    /// (name, rotary) per machine axis.
    axes: Vec<(String, bool)>,
}

/// A node map's entry: `AXIS=NODEID` in OPC UA's text form (`ns=2;s=...`, `ns=3;i=1001`).
pub fn parse_node(text: &str) -> Result<(String, NodeId), String> {
    let (axis, id) = text.split_once('=').ok_or_else(|| format!("'{text}': expected AXIS=NODEID"))?;
    let node: NodeId = id.trim().parse().map_err(|_| format!("'{id}': not an OPC UA node id (e.g. ns=2;s=/Channel/MachineAxis/actToolBasePos[u1,1])"))?;
    Ok((axis.trim().to_string(), node))
}

/// What browsing found: per machine axis, its ActPos node and the factor to SI.
struct Found {
    nodes: Vec<NodeId>,
    factors: Vec<f64>,
}

impl OpcUa {
    /// A server at `url`; `nodes` (axis -> node, given for every axis or none) replaces browsing the
    /// CNC model.
    pub fn new(url: &str, machine: &Machine, axis_map: BTreeMap<String, String>, measuring: Measuring, sampling: Duration, assume_mm_deg: bool, nodes: Vec<(String, NodeId)>) -> Result<OpcUa, String> {
        let axes: Vec<(String, bool)> = machine.axes.iter().map(|a| (a.name.clone(), a.kind == AxisKind::Rotary)).collect();
        let mut map = BTreeMap::new();
        for (axis, node) in nodes {
            let name = axes.iter().find(|(n, _)| n.eq_ignore_ascii_case(&axis)).map(|(n, _)| n.clone()).ok_or_else(|| format!("--opcua-node {axis}=...: the machine has no axis {axis}"))?;
            map.insert(name, node);
        }
        if !map.is_empty() {
            if let Some((missing, _)) = axes.iter().find(|(n, _)| !map.contains_key(n)) {
                return Err(format!("--opcua-node gives no node for axis {missing}: give one per axis, or none to browse the CNC model"));
            }
        }
        Ok(OpcUa { url: url.to_string(), measuring, sampling, axis_map, assume_mm_deg, nodes: map, security: Security::None, identity: None, axes })
    }

    /// Read until `keep_going` says stop, connecting again whenever the connection is lost; an
    /// address space without the axes is refused (`Err`), since trying again will not help.
    pub fn run(&self, keep_going: KeepGoing, on: &mut dyn FnMut(Event)) -> Result<(), String> {
        let runtime = tokio::runtime::Builder::new_current_thread().enable_all().build().map_err(|e| e.to_string())?;
        let mut retry = Retry::new();
        while keep_going() {
            // A session that got as far as its subscription: the next wait is the first again (the
            // waits of a start before the server listened, kept, held a restarted server's first
            // 2 s from the bridge).
            let connected = std::cell::Cell::new(false);
            let mut relay = |e: Event| {
                if matches!(e, Event::Connected(_)) {
                    connected.set(true);
                }
                on(e)
            };
            match runtime.block_on(self.session(keep_going, &mut relay)) {
                Ok(()) => return Ok(()),
                Err(Failure::Refused(why)) => return Err(why),
                Err(Failure::Down(why)) => relay(Event::Down(format!("OPC UA {}: {why}", self.url))),
            }
            if connected.get() {
                retry.reset();
            }
            if !retry.back_off(keep_going) {
                break;
            }
        }
        Ok(())
    }

    async fn session(&self, keep_going: KeepGoing<'_>, on: &mut dyn FnMut(Event)) -> Result<(), Failure> {
        // The client's own certificate (OPC UA Part 4 §5.4: every application has one, even on an
        // endpoint without security), made once and kept.
        let pki = pki_dir();
        let mut client = ClientBuilder::new()
            .application_name("fiveaxis-bridge")
            .application_uri("urn:fiveaxis:bridge")
            .product_uri("urn:fiveaxis")
            .pki_dir(pki)
            .create_sample_keypair(true)
            .trust_server_certs(true)
            // Connection losses are this module's to handle: browse again, subscribe again.
            .session_retry_limit(0)
            .session_timeout(60_000)
            .client()
            .map_err(|e| Failure::Refused(format!("OPC UA client: {}", e.join("; "))))?;
        let (policy, mode) = match self.security {
            Security::None => (SecurityPolicy::None, MessageSecurityMode::None),
            Security::Sign => (SecurityPolicy::Basic256Sha256, MessageSecurityMode::Sign),
            Security::SignAndEncrypt => (SecurityPolicy::Basic256Sha256, MessageSecurityMode::SignAndEncrypt),
        };
        let identity = match &self.identity {
            Some((user, password)) => IdentityToken::new_user_name(user.clone(), password.clone()),
            None => IdentityToken::Anonymous,
        };
        let (session, event_loop) = client
            .connect_to_matching_endpoint((self.url.as_str(), policy.to_str(), mode, UserTokenPolicy::anonymous()), identity)
            .await
            .map_err(|e| {
                // No endpoint with this security: the server is set up otherwise, retrying will not help.
                if e.status() == opcua::types::StatusCode::BadTcpEndpointUrlInvalid {
                    Failure::Refused(format!("the server offers no endpoint with security {:?} ({e})", self.security))
                } else {
                    Failure::Down(format!("connecting: {e}"))
                }
            })?;
        let mut handle = event_loop.spawn();
        // Connected, or the event loop ended (the server refused: it says why), or nothing for 10 s.
        let (connected, why) = tokio::select! {
            c = session.wait_for_connection() => (c, None),
            code = &mut handle => (false, code.ok()),
            _ = tokio::time::sleep(Duration::from_secs(10)) => (false, None),
        };
        if !connected {
            // Who we are, or our certificate, will not change by trying again.
            handle.abort();
            use opcua::types::StatusCode as S;
            return Err(match why {
                Some(code) if [S::BadUserAccessDenied, S::BadIdentityTokenInvalid, S::BadIdentityTokenRejected].contains(&code) => {
                    Failure::Refused(format!("the server refused the session's identity: {code} (user and FIVEAXIS_OPCUA_PASSWORD)"))
                }
                Some(code) if [S::BadSecurityChecksFailed, S::BadCertificateUntrusted, S::BadCertificateInvalid, S::BadSecurityPolicyRejected].contains(&code) => {
                    Failure::Refused(format!("the server refused the channel: {code} (it must trust the bridge's certificate, in its PKI directory's own/)"))
                }
                Some(code) => Failure::Down(format!("no session: {code}")),
                None => Failure::Down("no session within 10 s".into()),
            });
        }
        let result = self.subscribed(&session, &handle, keep_going, on).await;
        // Close the session while its event loop runs; once the loop has ended (the connection
        // lost) nothing can carry the request, and waiting for it delayed every reconnection by 2 s.
        if !handle.is_finished() {
            let _ = tokio::time::timeout(Duration::from_secs(2), session.disconnect()).await;
        }
        handle.abort();
        result
    }

    /// Browse, subscribe, and hand the values on until the connection ends or the caller stops.
    async fn subscribed(&self, session: &Arc<Session>, handle: &tokio::task::JoinHandle<opcua::types::StatusCode>, keep_going: KeepGoing<'_>, on: &mut dyn FnMut(Event)) -> Result<(), Failure> {
        let found = self.browse(session).await?;
        let gathered = Arc::new(Mutex::new(ByInstant::default()));
        let refused = Arc::new(Mutex::new(Vec::<String>::new()));
        let by_node: Arc<std::collections::HashMap<NodeId, usize>> = Arc::new(found.nodes.iter().cloned().enumerate().map(|(i, n)| (n, i)).collect());
        let (g, r, factors) = (gathered.clone(), refused.clone(), found.factors.clone());
        let callback = DataChangeCallback::new(move |dv: DataValue, item: &MonitoredItem| {
            let Some(&axis) = by_node.get(&item.item_to_monitor().node_id) else { return };
            match value_of(&dv) {
                Ok(Some(v)) => g.lock().unwrap_or_else(|e| e.into_inner()).push(stamp_of(&dv), axis, v * factors[axis]),
                Ok(None) => {}
                Err(why) => r.lock().unwrap_or_else(|e| e.into_inner()).push(format!("{}: {why}", item.item_to_monitor().node_id)),
            }
        });
        let sampling = self.sampling;
        let subscription = session
            .create_subscription(sampling, 60, 10, 0, 0, true, callback)
            .await
            .map_err(|e| Failure::Down(format!("creating the subscription: {e}")))?;
        let items: Vec<MonitoredItemCreateRequest> = found
            .nodes
            .iter()
            .map(|n| {
                let mut req: MonitoredItemCreateRequest = n.clone().into();
                req.requested_parameters.sampling_interval = sampling.as_secs_f64() * 1e3;
                // Every sample kept between two publishes (a late publish loses none).
                req.requested_parameters.queue_size = 100;
                req.requested_parameters.discard_oldest = true;
                req
            })
            .collect();
        let created = session
            .create_monitored_items(subscription, TimestampsToReturn::Both, items)
            .await
            .map_err(|e| Failure::Down(format!("creating the monitored items: {e}")))?;
        for (c, (name, _)) in created.iter().zip(&self.axes) {
            if !c.result.status_code.is_good() {
                return Err(Failure::Refused(format!("axis {name}: the server refused to monitor its position: {}", c.result.status_code)));
            }
        }
        on(Event::Connected(format!("OPC UA {}: {} axes subscribed, sampled every {} ms", self.url, found.nodes.len(), sampling.as_millis())));
        loop {
            tokio::time::sleep(Duration::from_millis(20)).await;
            let mut batch = std::mem::take(&mut *gathered.lock().unwrap_or_else(|e| e.into_inner()));
            batch.drain(|r| on(Event::Report(r)));
            for why in std::mem::take(&mut *refused.lock().unwrap_or_else(|e| e.into_inner())) {
                on(Event::Refused(why));
            }
            if !keep_going() {
                return Ok(());
            }
            if handle.is_finished() {
                return Err(Failure::Down("the connection was lost".into()));
            }
        }
    }

    /// The nodes given, with the units their `EngineeringUnits` property says (if any).
    async fn given(&self, session: &Session) -> Result<Found, Failure> {
        let mut nodes = Vec::new();
        let mut factors = Vec::new();
        for (axis, rotary) in &self.axes {
            let node = self.nodes[axis].clone();
            // The node must be there and readable (a mistyped path is refused, not waited for).
            let v = session
                .read(&[ReadValueId { node_id: node.clone(), attribute_id: AttributeId::Value as u32, ..Default::default() }], TimestampsToReturn::Neither, 0.0)
                .await
                .map_err(|e| Failure::Down(format!("reading {node}: {e}")))?;
            if let Some(status) = v.first().and_then(|d| d.status).filter(|s| !s.is_good()) {
                return Err(Failure::Refused(format!("axis {axis}: node {node}: {status}")));
            }
            let eu = self.follow(session, &node, &[(0, "EngineeringUnits")]).await?;
            let units = self.units(session, eu).await?;
            factors.push(model::position_factor(axis, *rotary, units.as_ref().map(|(u, i)| (u.as_str(), *i)), self.assume_mm_deg).map_err(Failure::Refused)?);
            nodes.push(node);
        }
        Ok(Found { nodes, factors })
    }

    /// An `EngineeringUnits` property's namespace URI and unit id.
    async fn units(&self, session: &Session, node: Option<NodeId>) -> Result<Option<(String, i32)>, Failure> {
        let Some(eu) = node else { return Ok(None) };
        let v = session
            .read(&[ReadValueId { node_id: eu, attribute_id: AttributeId::Value as u32, ..Default::default() }], TimestampsToReturn::Neither, 0.0)
            .await
            .map_err(|e| Failure::Down(format!("reading EngineeringUnits: {e}")))?;
        Ok(match v.first().and_then(|d| d.value.as_ref()) {
            Some(Variant::ExtensionObject(x)) => x.inner_as::<EUInformation>().map(|e| (e.namespace_uri.as_ref().to_string(), e.unit_id)),
            _ => None,
        })
    }

    /// The machine's axes in the CNC model: their ActPos nodes and units.
    async fn browse(&self, session: &Session) -> Result<Found, Failure> {
        if !self.nodes.is_empty() {
            return self.given(session).await;
        }
        let down = |what: &str, e: &dyn std::fmt::Display| Failure::Down(format!("{what}: {e}"));
        let ns_array = session
            .read(&[ReadValueId { node_id: NodeId::new(0, 2255u32), attribute_id: AttributeId::Value as u32, ..Default::default() }], TimestampsToReturn::Neither, 0.0)
            .await
            .map_err(|e| down("reading the namespace array", &e))?;
        let namespaces: Vec<String> = match ns_array.first().and_then(|d| d.value.as_ref()) {
            Some(Variant::Array(a)) => a.values.iter().map(|v| if let Variant::String(s) = v { s.as_ref().to_string() } else { String::new() }).collect(),
            _ => Vec::new(),
        };
        let ns = namespaces.iter().position(|u| u == model::CNC_NAMESPACE).ok_or_else(|| Failure::Refused(format!("the server has no OPC 40502 CNC model (namespace {} not among {namespaces:?})", model::CNC_NAMESPACE)))? as u16;
        let list = self.follow(session, &NodeId::new(0, 85u32), &[(ns, model::CNC_INTERFACE), (ns, model::CNC_AXIS_LIST)]).await?.ok_or_else(|| {
            Failure::Refused(format!("no Objects/{}/{} in the server's address space", model::CNC_INTERFACE, model::CNC_AXIS_LIST))
        })?;
        let browsed = session
            .browse(
                &[BrowseDescription {
                    node_id: list.clone(),
                    browse_direction: BrowseDirection::Forward,
                    reference_type_id: ReferenceTypeId::HierarchicalReferences.into(),
                    include_subtypes: true,
                    node_class_mask: NodeClass::Object as u32,
                    result_mask: 0x3f,
                }],
                1000,
                None,
            )
            .await
            .map_err(|e| down("browsing the axis list", &e))?;
        let children: Vec<(String, NodeId)> =
            browsed.first().and_then(|r| r.references.clone()).unwrap_or_default().into_iter().map(|r| (r.browse_name.name.as_ref().to_string(), r.node_id.node_id)).collect();
        let names: Vec<&str> = children.iter().map(|(n, _)| n.as_str()).collect();
        let mut nodes = Vec::new();
        let mut factors = Vec::new();
        for (axis, rotary) in &self.axes {
            let want = self.axis_map.get(axis).unwrap_or(axis);
            let (_, node) = children.iter().find(|(n, _)| n.eq_ignore_ascii_case(want)).ok_or_else(|| {
                Failure::Refused(format!("axis {axis}: no CncAxis '{want}' in {}/{} (its axes: {names:?}; name one with --axis-map {axis}=NAME)", model::CNC_INTERFACE, model::CNC_AXIS_LIST))
            })?;
            let pos = self.measuring.browse_name();
            let act = self.follow(session, node, &[(ns, pos), (ns, model::ACT_POS)]).await?.ok_or_else(|| Failure::Refused(format!("axis {axis}: no {pos}/{} under CncAxis '{want}'", model::ACT_POS)))?;
            // EngineeringUnits: the CNC model's own (ns CNC) or the standard property's name.
            let mut eu_node = self.follow(session, node, &[(ns, pos), (ns, "EngineeringUnits")]).await?;
            if eu_node.is_none() {
                eu_node = self.follow(session, node, &[(ns, pos), (0, "EngineeringUnits")]).await?;
            }
            let units = self.units(session, eu_node).await?;
            let factor = model::position_factor(axis, *rotary, units.as_ref().map(|(u, i)| (u.as_str(), *i)), self.assume_mm_deg).map_err(Failure::Refused)?;
            nodes.push(act);
            factors.push(factor);
        }
        Ok(Found { nodes, factors })
    }

    /// The node reached from `start` by hierarchical references with these browse names (None: no such path).
    async fn follow(&self, session: &Session, start: &NodeId, path: &[(u16, &str)]) -> Result<Option<NodeId>, Failure> {
        let elements = path
            .iter()
            .map(|(ns, name)| RelativePathElement { reference_type_id: ReferenceTypeId::HierarchicalReferences.into(), is_inverse: false, include_subtypes: true, target_name: QualifiedName::new(*ns, *name) })
            .collect();
        let results = session
            .translate_browse_paths_to_node_ids(&[BrowsePath { starting_node: start.clone(), relative_path: RelativePath { elements: Some(elements) } }])
            .await
            .map_err(|e| Failure::Down(format!("translating a browse path: {e}")))?;
        Ok(results.into_iter().next().filter(|r| r.status_code.is_good()).and_then(|r| r.targets).and_then(|t| t.into_iter().next()).map(|t| t.target_id.node_id))
    }
}

/// A position's value (None: no good value, e.g. the server's Bad status while an axis is not
/// referenced); a value that is not a number is an error.
fn value_of(dv: &DataValue) -> Result<Option<f64>, String> {
    if dv.status.is_some_and(|s| !s.is_good()) {
        return Ok(None);
    }
    let v = match dv.value.as_ref() {
        None | Some(Variant::Empty) => return Ok(None),
        Some(Variant::Double(x)) => *x,
        Some(Variant::Float(x)) => f64::from(*x),
        Some(Variant::Int32(x)) => f64::from(*x),
        Some(Variant::Int64(x)) => *x as f64,
        Some(other) => return Err(format!("a position of type {:?}, not a number", other.type_id())),
    };
    if v.is_finite() {
        Ok(Some(v))
    } else {
        Err(format!("a position of {v}"))
    }
}

/// When the value was taken: its SourceTimestamp (else the server's, else now).
fn stamp_of(dv: &DataValue) -> Stamp {
    match dv.source_timestamp.or(dv.server_timestamp) {
        Some(t) if !t.is_null() => {
            let c = t.as_chrono();
            Stamp { sec: c.timestamp(), nanosec: c.timestamp_subsec_nanos() }
        }
        _ => Stamp::now(),
    }
}

/// Where the client keeps its certificate and the servers' it has seen: `$FIVEAXIS_OPCUA_PKI`, else
/// `$XDG_STATE_HOME/fiveaxis/opcua-pki` or `~/.local/state/fiveaxis/opcua-pki`.
fn pki_dir() -> std::path::PathBuf {
    if let Some(d) = std::env::var_os("FIVEAXIS_OPCUA_PKI") {
        return d.into();
    }
    let state = std::env::var_os("XDG_STATE_HOME")
        .map(std::path::PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| std::path::PathBuf::from(h).join(".local/state")))
        .unwrap_or_else(std::env::temp_dir);
    state.join("fiveaxis/opcua-pki")
}
