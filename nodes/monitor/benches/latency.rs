//! Commanded-publish -> status-received latency over DDS at 1 kHz (target p99 <= 1 ms on loopback).
//!
//! Three participants in one process, talking RTPS over UDP loopback: a commander publishes SING.I's
//! commanded states at 1 kHz; a monitor takes each, evaluates it and publishes its status; an
//! observer receives the statuses. Latency = status received - state published, per sample.
//! Re-executes itself inside a private loopback-only network namespace (launch-free-scripts/netns-run).

use fiveaxis::topics;
use fiveaxis::job;
use fiveaxis::live::commander::commanded_states;
use fiveaxis::live::monitor::{Monitor, MonitorConfig};
use fiveaxis::machine::Machine;
use fiveaxis_bus::{state_qos, Bus, CommonArgs, Pacer};
use fiveaxis_msgs::{AxisState, SingularityStatus};
use std::collections::HashMap;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

fn args(name: &str) -> CommonArgs {
    CommonArgs { namespace: "/bench".into(), machine: Default::default(), remaps: vec![], node_name: Some(name.into()), use_sim_time: false }
}

fn main() -> anyhow::Result<()> {
    if std::env::var_os("FIVEAXIS_IN_NETNS").is_none() {
        let script = concat!(env!("CARGO_MANIFEST_DIR"), "/../../launch-free-scripts/netns-run");
        let status = std::process::Command::new(script)
            .arg(std::env::current_exe()?)
            .args(std::env::args_os().skip(1))
            .env("FIVEAXIS_IN_NETNS", "1")
            .status()?;
        std::process::exit(status.code().unwrap_or(1));
    }
    let n: usize = std::env::var("FIVEAXIS_BENCH_SAMPLES").ok().and_then(|s| s.parse().ok()).unwrap_or(5000);
    let machine = Machine::hermle_c600u();
    let j = job::run("bundled:SING.I", &machine, &Default::default())?;
    // The cutting pass, where the monitor has the most to do.
    let states: Vec<AxisState> = commanded_states(&j.trajectory, &machine)
        .into_iter()
        .filter(|s| s.block_number >= 110)
        .take(n)
        .enumerate()
        .map(|(k, mut s)| {
            s.header.stamp = fiveaxis_msgs::Time::from_secs(k as f64 * 1e-3);
            s
        })
        .collect();

    let mut cmd = Bus::new("bench_commander", &args("bench_commander"), &fiveaxis_bus::RosOptions::default())?;
    let mut mon = Bus::new("bench_monitor", &args("bench_monitor"), &fiveaxis_bus::RosOptions::default())?;
    let mut obs = Bus::new("bench_observer", &args("bench_observer"), &fiveaxis_bus::RosOptions::default())?;
    let state_pub = cmd.publisher::<AxisState>(topics::COMMANDED_STATE.name, state_qos())?;
    let state_sub = mon.subscription::<AxisState>(topics::COMMANDED_STATE.name, state_qos())?;
    let status_pub = mon.publisher::<SingularityStatus>(topics::STATUS.name, state_qos())?;
    let status_sub = obs.subscription::<SingularityStatus>(topics::STATUS.name, state_qos())?;

    let sent: Arc<Mutex<HashMap<u64, Instant>>> = Arc::default();
    let topic = mon.resolve(topics::COMMANDED_STATE.name);
    let m = machine.clone();
    std::thread::spawn(move || {
        let mut monitor = Monitor::new(&m, MonitorConfig::default());
        let start = Instant::now();
        loop {
            let Ok((st, _)) = smol::block_on(state_sub.async_take()) else { continue };
            if let Ok(status) = monitor.on_state(&topic, &st, start.elapsed().as_secs_f64()) {
                let _ = status_pub.publish(status);
            }
        }
    });
    let received: Arc<Mutex<Vec<Duration>>> = Arc::default();
    {
        let (sent, received) = (sent.clone(), received.clone());
        std::thread::spawn(move || loop {
            let Ok((status, _)) = smol::block_on(status_sub.async_take()) else { continue };
            let now = Instant::now();
            if let Some(t0) = sent.lock().unwrap().get(&status.header.stamp.as_nanos()) {
                received.lock().unwrap().push(now - *t0);
            }
        });
    }
    let shutdown = fiveaxis_bus::Shutdown::install()?;
    if !cmd.wait_for_subscriber(&state_pub, Duration::from_secs(10), &shutdown) {
        anyhow::bail!("the monitor did not subscribe");
    }
    std::thread::sleep(Duration::from_millis(500));
    let pacer = Pacer::new(Some(1.0));
    for st in &states {
        pacer.wait_until(st.header.stamp.as_secs());
        sent.lock().unwrap().insert(st.header.stamp.as_nanos(), Instant::now());
        state_pub.publish(st.clone()).map_err(|e| anyhow::anyhow!("{e:?}"))?;
    }
    std::thread::sleep(Duration::from_millis(500));
    let mut lat = received.lock().unwrap().clone();
    lat.sort();
    let q = |p: f64| lat[((lat.len() as f64 - 1.0) * p).round() as usize].as_secs_f64() * 1e6;
    println!("DDS latency, commanded publish -> status received, {} samples at 1 kHz over UDP loopback:", states.len());
    if lat.is_empty() {
        anyhow::bail!("no status received");
    }
    println!(
        "  received {} ({} lost); p50 {:.0} us, p90 {:.0} us, p99 {:.0} us, max {:.0} us (target p99 <= 1000 us)",
        lat.len(),
        states.len() - lat.len(),
        q(0.5),
        q(0.9),
        q(0.99),
        q(1.0)
    );
    Ok(())
}
