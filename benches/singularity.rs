//! Singularity-analysis throughput on one core (target: >= 20 M samples/s).
//!
//! `per_sample`: the per-sample math of the monitor (distance to the singularity, seed 001 eq. 5,
//! seed 002 eq. 5 feed limit over five axes) on the samples of the paper's singular path.
//! `whole_program`: the full offline analysis of SING.I (spline geometry, regions, summary included).

use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use fiveaxis::job::{self, JobOptions};
use fiveaxis::machine::Machine;
use fiveaxis::path::{PathOptions, SegmentWindow};
use fiveaxis::singularity::{analyze, distance, FeedLimiter, PathGeometry};

fn per_sample(c: &mut Criterion) {
    let m = Machine::hermle_c600u();
    let traj = fiveaxis::path::BuiltinPath::by_name("paper-sing")
        .unwrap()
        .trajectory(&m, &PathOptions { period: 1e-5, ..Default::default() })
        .unwrap();
    let mut geo = PathGeometry::new();
    let mut window = SegmentWindow::new(traj.segments.iter().cloned());
    // Precompute the geometric derivatives: the bench measures the per-sample math, as the live
    // monitor runs it with derivatives from its look-ahead.
    let rows: Vec<_> = traj
        .samples(&m)
        .map(|s| (s.axis, s.axis_rate, [s.q[3], s.q[4]], s.feed, geo.derivatives(s.segment, s.s, &mut window).unwrap()))
        .collect();
    let sd = m.singular_direction();
    let limiter = FeedLimiter::new(&m.limits());
    let mut g = c.benchmark_group("singularity");
    g.throughput(Throughput::Elements(rows.len() as u64));
    g.bench_function("per_sample", |b| {
        b.iter(|| {
            let mut acc = 0.0;
            for (axis, rate, rot, feed, (d1, d2, d3)) in &rows {
                let d = distance(axis, &sd);
                let r = m.chain.secondary_rate(axis, rate, rot);
                let f = limiter.limit(*feed, d1, d2, d3);
                acc += d + r + f.feed;
            }
            black_box(acc)
        })
    });
    g.finish();
}

fn whole_program(c: &mut Criterion) {
    let m = Machine::hermle_c600u();
    let job = job::run("bundled:SING.I", &m, &JobOptions::default()).unwrap();
    let mut g = c.benchmark_group("singularity");
    g.throughput(Throughput::Elements(job.trajectory.sample_count() as u64));
    g.sample_size(20);
    g.bench_function("whole_program_sing", |b| b.iter(|| black_box(analyze(&job.trajectory, &m, &Default::default()))));
    g.finish();
}

criterion_group!(benches, per_sample, whole_program);
criterion_main!(benches);
