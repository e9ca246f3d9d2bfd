use geared_rotor::radau5::test_problems::{all_rows, run_row};
fn main() {
    let which = std::env::args().nth(1).unwrap_or("amp1t".into());
    let tol: f64 = std::env::args()
        .nth(2)
        .map(|s| s.parse().unwrap())
        .unwrap_or(1e-4);
    let tend: f64 = std::env::args()
        .nth(3)
        .map(|s| s.parse().unwrap())
        .unwrap_or(0.0);
    let rows: Vec<_> = all_rows()
        .filter(|r| r.problem == which && r.rtol == tol && (tend == 0.0 || r.t_end == tend))
        .collect();
    let n = 2000;
    let t = std::time::Instant::now();
    for _ in 0..n {
        for r in &rows {
            std::hint::black_box(run_row(r).ok());
        }
    }
    println!(
        "{} rows, {:.2} us per solve",
        rows.len(),
        t.elapsed().as_secs_f64() / n as f64 / rows.len() as f64 * 1e6
    );
}
