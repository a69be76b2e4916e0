//! The simulator's speed relative to real time on SING.I (target >= 1000x), and the planner's
//! SING.I traverse times with the Hermle's A/C limits (150 deg/s, 600 deg/s^2), printed beside the
//! reference figure the issue gives for LinuxCNC 2.9's planner (4.80 s, exceeding some joint limits).

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use fiveaxis::job;
use fiveaxis::live::simulator::{simulate, SimConfig};
use fiveaxis::machine::Machine;
use fiveaxis::planner::limit_ratios;

fn simulator(c: &mut Criterion) {
    let m = Machine::hermle_c600u();
    let j = job::run("bundled:SING.I", &m, &Default::default()).unwrap();
    let a = &m.axes[m.axis_index("A").unwrap()].limits;
    let cax = &m.axes[m.axis_index("C").unwrap()].limits;
    // One run for the figures.
    let t = std::time::Instant::now();
    let sim = simulate(&j.trajectory, &m, &SimConfig::default());
    let elapsed = t.elapsed().as_secs_f64();
    let ratios = limit_ratios(&sim.q, sim.period, &m.limits());
    let worst = ratios.iter().fold([0.0f64; 3], |w, r| [w[0].max(r[0]), w[1].max(r[1]), w[2].max(r[2])]);
    let cut: Vec<usize> = (0..sim.q.len())
        .filter(|&k| j.trajectory.segments[sim.segment[k]].number.is_some_and(|n| (120..=610).contains(&n)))
        .collect();
    let cut_time = cut.len() as f64 * sim.period;
    println!(
        "SING.I on {}: A/C {:.0}/{:.0} deg/s, {:.0}/{:.0} deg/s^2",
        m.name,
        a.velocity.to_degrees(),
        cax.velocity.to_degrees(),
        a.acceleration.to_degrees(),
        cax.acceleration.to_degrees()
    );
    println!("  whole program: {:.2} s simulated ({:.2} s at the programmed feed)", sim.duration(), j.trajectory.duration());
    println!("  cutting pass N120-N610 (x 0 -> 50 mm): {cut_time:.2} s (1.50 s at F2000; LinuxCNC 2.9 reference: 4.80 s)");
    println!("  largest |v|/v_max {:.3}, |a|/a_max {:.3}, |j|/j_max {:.3}", worst[0], worst[1], worst[2]);
    println!("  one simulation: {:.1} ms = {:.0}x real time", elapsed * 1e3, sim.duration() / elapsed);
    let mut g = c.benchmark_group("simulator");
    g.sample_size(20);
    g.bench_function("simulate_sing", |b| b.iter(|| black_box(simulate(&j.trajectory, &m, &SimConfig::default()))));
    g.finish();
}

criterion_group!(benches, simulator);
criterion_main!(benches);
