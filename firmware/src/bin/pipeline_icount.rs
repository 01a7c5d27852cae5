//! Instruction counts of the module pipeline on a cascade-86, 512-sample, 2-loop frame with 4
//! objects, on the Cortex-M7 under `qemu-system-arm -icount shift=0`.
//!
//! Prints `ICOUNT stage=… instructions=…` for the frame stage (sums of every chirp, in-place
//! range spectra, peak scan) and for each object (SIC + search), then `PIPELINE depth_mm=…` per
//! object; then the same with `calibrated_` before each stage for the frame of an imperfect
//! board (`bench_scene::chirp_on_board`) summed through the calibration that undoes it, after
//! the calibration table's one-off cost. The synthetic chirps
//! are generated outside the measured spans.
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(target_os = "none")]
mod app {
    use cortex_m_rt::entry;
    use cortex_m_semihosting::hprintln;
    use firmware::bench_scene::{self, ARENA_WORDS, N};
    use firmware::board::{INSTRUCTIONS_PER_TICK, Timer0};
    use firmware::module::CALIBRATION_WORDS;
    use metamoran_dsp::fixed::CQ15;
    use metamoran_dsp::pipeline::{ChannelCoefficients, Edge};

    firmware::hard_fault_exits!();

    static mut ARENA: [u32; ARENA_WORDS] = [0; ARENA_WORDS];

    /// The calibration table of the calibrated frame (the module keeps it in its scratch).
    static mut TABLE: [u32; CALIBRATION_WORDS] = [0; CALIBRATION_WORDS];

    /// Counts one frame of the budget scene (calibrated by `coefficients` when given), printing
    /// its stages with `prefix`; the frame's total.
    fn frame(
        edge: &Edge,
        arena: &mut [u32],
        coefficients: Option<&ChannelCoefficients<'_>>,
        prefix: &str,
        timer: &Timer0,
        count: &impl Fn(u32) -> u32,
    ) -> Option<u32> {
        let config = bench_scene::config();
        let mut frame = match coefficients {
            None => edge.start(arena),
            Some(k) => edge.start_calibrated(arena, k),
        }
        .ok()?;
        let mut chirp = [CQ15::default(); N];
        let mut sums = 0u32;
        for c in 0..config.chirps_per_frame() {
            for rx in 0..config.rx_count() {
                match coefficients {
                    None => bench_scene::chirp(&config, c, rx, &mut chirp),
                    Some(_) => bench_scene::chirp_on_board(&config, c, rx, &mut chirp),
                }
                let x = core::hint::black_box(&chirp);
                sums += timer.ticks(|| {
                    let _ = match coefficients {
                        None => edge.push(&mut frame, c, rx, x),
                        Some(k) => edge.push_calibrated(&mut frame, c, rx, x, k),
                    };
                });
            }
        }
        let mut row = [CQ15::default(); N];
        let (mut az, mut powers) = ([CQ15::default(); 256], [0u64; 768]);
        let mut scene = None;
        let finish = timer.ticks(|| {
            scene = edge.finish(frame, &mut row, &mut az, &mut powers).ok();
        });
        let mut scene = scene?;
        hprintln!("ICOUNT stage={}sums instructions={}", prefix, count(sums));
        hprintln!(
            "ICOUNT stage={}spectra_and_peaks instructions={}",
            prefix,
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
            hprintln!(
                "ICOUNT stage={}object{}_sic instructions={}",
                prefix,
                i,
                count(sic)
            );
            hprintln!(
                "ICOUNT stage={}object{}_search instructions={}",
                prefix,
                i,
                count(search)
            );
            match report {
                Some(r) => hprintln!(
                    "PIPELINE {}object={} depth_mm={} cancelled={} detected={} macs={}",
                    prefix,
                    i,
                    (r.search.depth_m * 1000.0) as i32,
                    r.cancelled,
                    r.detected(),
                    r.search.macs
                ),
                None => hprintln!("PIPELINE {}object={} error", prefix, i),
            }
        }
        Some(total)
    }

    #[entry]
    fn main() -> ! {
        let stack = firmware::board::StackGauge::paint();
        let timer = Timer0::start();
        let overhead = timer.ticks(|| ());
        let count = |t: u32| t.saturating_sub(overhead) * INSTRUCTIONS_PER_TICK;
        // SAFETY: the only references to ARENA and TABLE, taken once before anything else runs.
        let (arena, table) = unsafe {
            (
                &mut *core::ptr::addr_of_mut!(ARENA),
                &mut *core::ptr::addr_of_mut!(TABLE),
            )
        };
        let Ok(edge) = Edge::new(&core::hint::black_box(bench_scene::config())) else {
            hprintln!("ICOUNT error=config");
            firmware::board::exit(false)
        };
        let Some(total) = frame(&edge, arena, None, "", &timer, &count) else {
            hprintln!("ICOUNT error=frame");
            firmware::board::exit(false)
        };
        hprintln!("ICOUNT stage=frame instructions={}", total);
        // The same frame calibrated: the table once per configuration, then the frame.
        let Some(calibration) = bench_scene::calibration() else {
            hprintln!("ICOUNT error=calibration");
            firmware::board::exit(false)
        };
        let mut coefficients = None;
        let build = timer.ticks(|| coefficients = edge.calibrate(&calibration, table).ok());
        let Some(coefficients) = coefficients else {
            hprintln!("ICOUNT error=calibration");
            firmware::board::exit(false)
        };
        hprintln!(
            "ICOUNT stage=calibration_table instructions={}",
            count(build)
        );
        let Some(calibrated) = frame(
            &edge,
            arena,
            Some(&coefficients),
            "calibrated_",
            &timer,
            &count,
        ) else {
            hprintln!("ICOUNT error=calibrated_frame");
            firmware::board::exit(false)
        };
        hprintln!("ICOUNT stage=calibrated_frame instructions={}", calibrated);
        hprintln!("STACK stack_bytes={}", stack.high_water());
        firmware::board::exit(true)
    }
}

#[cfg(not(target_os = "none"))]
fn main() {
    eprintln!("pipeline-icount runs on thumbv7em-none-eabihf under QEMU: metamoran bench m7");
    std::process::exit(2);
}
