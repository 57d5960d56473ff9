//! Prints a generated assembly-line cell (see `benches/line.rs`), for measuring a whole
//! `cellc build` run: `cargo run --release --example line_cell -- 50 100 4 > cells/line50.cell`.

#[path = "../benches/line.rs"]
mod line;

fn main() {
    let args: Vec<usize> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let arms = args.first().copied().unwrap_or(50);
    let grasps = args.get(1).copied().unwrap_or(100);
    let rests = args.get(2).copied().unwrap_or(4);
    print!("{}", line::line_cell(arms, grasps, rests));
}
