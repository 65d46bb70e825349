//! Makes the RGB-to-spectrum coefficient table (linear sRGB, D65) that
//! `penumbra_core::spectral::RgbToSpectrum::srgb` builds into the binary.
//!
//! usage: cargo run --release -p penumbra-core --example make_rgb2spec -- RES OUT

use penumbra_core::spectral::rgb2spec_opt;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let (Some(res), Some(out)) = (args.get(1).and_then(|r| r.parse::<usize>().ok()), args.get(2)) else {
        eprintln!("usage: make_rgb2spec RES OUT");
        std::process::exit(2);
    };
    if !(2..=256).contains(&res) {
        eprintln!("make_rgb2spec: RES must be from 2 to 256");
        std::process::exit(2);
    }
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let start = std::time::Instant::now();
    let (table, worst) = rgb2spec_opt::build(res, threads);
    std::fs::write(out, table.to_bytes()).unwrap_or_else(|e| {
        eprintln!("make_rgb2spec: cannot write {out}: {e}");
        std::process::exit(1);
    });
    println!(
        "wrote {out}: resolution {res}, {} bytes, largest CIELAB residual {worst:.2e}, {:.1} s on {threads} threads",
        table.size().1,
        start.elapsed().as_secs_f64()
    );
}
