//! Instruction counts of the module pipeline on a cascade-86, 512-sample, 2-loop frame with 4
//! objects, on the Cortex-M7 under `qemu-system-arm -icount shift=0`.
//!
//! Prints `ICOUNT stage=… instructions=…` for the frame stage (sums of every chirp, in-place
//! range spectra, peak scan) and for each object (SIC + search), then `PIPELINE depth_mm=…` per
//! object. The synthetic chirps are generated outside the measured spans.
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(target_os = "none")]
mod app {
    use cortex_m_rt::entry;
    use cortex_m_semihosting::hprintln;
    use firmware::bench_scene::{self, ARENA_WORDS, N};
    use firmware::board::{INSTRUCTIONS_PER_TICK, Timer0};
    use metamoran_dsp::fixed::CQ15;
    use metamoran_dsp::pipeline::Edge;

    firmware::hard_fault_exits!();

    static mut ARENA: [u32; ARENA_WORDS] = [0; ARENA_WORDS];

    #[entry]
    fn main() -> ! {
        let stack = firmware::board::StackGauge::paint();
        let timer = Timer0::start();
        let overhead = timer.ticks(|| ());
        let count = |t: u32| t.saturating_sub(overhead) * INSTRUCTIONS_PER_TICK;
        // SAFETY: the only reference to ARENA, taken once before anything else runs.
        let arena = unsafe { &mut *core::ptr::addr_of_mut!(ARENA) };
        let config = bench_scene::config();
        let Ok(edge) = Edge::new(&config) else {
            hprintln!("ICOUNT error=config");
            firmware::board::exit(false)
        };
        let Ok(mut frame) = edge.start(arena) else {
            hprintln!("ICOUNT error=arena");
            firmware::board::exit(false)
        };
        let mut chirp = [CQ15::default(); N];
        let mut sums = 0u32;
        for c in 0..config.chirps_per_frame() {
            for rx in 0..config.rx_count() {
                bench_scene::chirp(&config, c, rx, &mut chirp);
                sums += timer.ticks(|| {
                    let _ = edge.push(&mut frame, c, rx, core::hint::black_box(&chirp));
                });
            }
        }
        let mut row = [CQ15::default(); N];
        let (mut az, mut powers) = ([CQ15::default(); 256], [0u64; 768]);
        let mut scene = None;
        let finish = timer.ticks(|| {
            scene = edge.finish(frame, &mut row, &mut az, &mut powers).ok();
        });
        let Some(mut scene) = scene else {
            hprintln!("ICOUNT error=finish");
            firmware::board::exit(false)
        };
        hprintln!("ICOUNT stage=sums instructions={}", count(sums));
        hprintln!(
            "ICOUNT stage=spectra_and_peaks instructions={}",
            count(finish)
        );
        let mut scores = [0.0f32; N];
        let mut total = count(sums) + count(finish);
        for (i, hint) in bench_scene::hints().iter().enumerate() {
            let mut report = None;
            let mut reflectors = heapless::Vec::new();
            let sic = timer.ticks(|| reflectors = edge.cancel(&scene, hint));
            let search = timer
                .ticks(|| report = edge.search(&mut scene, hint, &reflectors, &mut scores).ok());
            total += count(sic) + count(search);
            hprintln!("ICOUNT stage=object{}_sic instructions={}", i, count(sic));
            hprintln!(
                "ICOUNT stage=object{}_search instructions={}",
                i,
                count(search)
            );
            match report {
                Some(r) => hprintln!(
                    "PIPELINE object={} depth_mm={} cancelled={} detected={} macs={}",
                    i,
                    (r.search.depth_m * 1000.0) as i32,
                    r.cancelled,
                    r.detected(),
                    r.search.macs
                ),
                None => hprintln!("PIPELINE object={} error", i),
            }
        }
        hprintln!("ICOUNT stage=frame instructions={}", total);
        hprintln!("STACK stack_bytes={}", stack.high_water());
        firmware::board::exit(true)
    }
}

#[cfg(not(target_os = "none"))]
fn main() {
    eprintln!("pipeline-icount runs on thumbv7em-none-eabihf under QEMU: metamoran bench m7");
    std::process::exit(2);
}
