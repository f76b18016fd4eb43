//! The machine's effective clock, for comparing timings taken on different
//! days (a shared VM's clock and neighbours change; see
//! docs/benchmarks.md).
//!
//! ```sh
//! cargo run --release --example clock      # 5 runs: G dependent additions per second
//! ```
//!
//! A chain of dependent integer additions runs at one per cycle on every
//! x86-64 core of the last 15 years, so additions per second are the
//! clock the program gets. Other architectures print a note and stop.
use std::time::Instant;

#[cfg(target_arch = "x86_64")]
fn additions_per_second(n: u64) -> f64 {
    let mut x = 0u64;
    let t = Instant::now();
    for _ in 0..n {
        // SAFETY: four register additions, no memory, no flags read after
        unsafe {
            std::arch::asm!(
                "add {x}, 1", "add {x}, 1", "add {x}, 1", "add {x}, 1",
                x = inout(reg) x,
                options(nomem, nostack),
            )
        };
    }
    let dt = t.elapsed().as_secs_f64();
    assert_eq!(x, 4 * n);
    4.0 * n as f64 / dt
}

fn main() {
    #[cfg(target_arch = "x86_64")]
    for _ in 0..5 {
        let r = additions_per_second(500_000_000);
        println!(
            "{:.2} G dependent additions/s (about the clock in GHz)",
            r / 1e9
        );
    }
    #[cfg(not(target_arch = "x86_64"))]
    println!("clock: only written for x86-64");
}
