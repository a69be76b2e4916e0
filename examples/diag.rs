fn main() {
    let p = std::env::args().nth(1).unwrap();
    let prog = fiveaxis::program::load(std::path::Path::new(&p), None, &Default::default()).unwrap();
    for l in prog.report() { println!("{l}"); }
    println!("blocks {} name {:?}", prog.blocks.len(), prog.name);
    for b in prog.blocks.iter().filter(|b| matches!(b.number, Some(450..=500))) { println!("{:?} {:?}", b.number, b.targets.x.map(|v| v*1000.0)); }
}
