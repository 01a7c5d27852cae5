//! `metamoran bench m7`: the module's budgets, measured on the release firmware.
//!
//! * flash and RAM: `size -A` of the `edge` firmware (flash = vector table + text + rodata +
//!   data; RAM = data + bss + uninit, the static frame arena included);
//! * stack: high-water mark by stack painting, the larger of the `pipeline-icount` run and an
//!   `edge` session on a simulated cascade bundle;
//! * instructions per frame: `pipeline-icount` under `qemu-system-arm -icount shift=0` on the
//!   cascade-86, 512-sample, 4-object budget frame (goal 24 M: half of a 100 ms frame at 480 MHz),
//!   and on the same frame from an imperfect board calibrated in the range stage;
//! * telemetry: wire bytes of the uplink frames a frame produces, per object and per frame.

use metamoran_dsp::wire::{
    Alternative, FrameSummary, Key, MAX_WIRE, ObjectResult, Score, Sender, Stream, Uplink,
};
use metamoran_edge::qemu;
use serde::Serialize;
use std::path::Path;
use std::process::Command;
use std::time::Duration;

/// Instructions per frame the module may spend (50 % of 100 ms at 480 MHz, one per cycle).
pub const INSTRUCTION_BUDGET: u64 = 24_000_000;
/// RAM the firmware may use, bytes.
pub const RAM_BUDGET: u64 = 512 * 1024;
/// Flash of the module, bytes.
pub const FLASH_BUDGET: u64 = 2 * 1024 * 1024;

/// The report (`--json` prints the first five fields' names as the issue specifies).
#[derive(Clone, Debug, Serialize)]
pub struct Budget {
    /// Flash bytes of the release `edge` firmware.
    pub flash_bytes: u64,
    /// Static RAM bytes of the release `edge` firmware (frame arena included).
    pub ram_bytes: u64,
    /// Stack high-water mark, bytes.
    pub stack_bytes: u64,
    /// Instructions for the budget frame (4 objects).
    pub instructions_per_frame: u64,
    /// Instructions for the same frame from an imperfect board, calibrated in the range stage
    /// (`bench_scene::chirp_on_board` and the calibration that undoes it).
    pub instructions_per_calibrated_frame: u64,
    /// Instructions to build the calibration table, once per configuration.
    pub calibration_table_instructions: u64,
    /// Uplink bytes each object adds to its frame's results message (frame number, summary,
    /// header, tag and COBS are per frame: see `telemetry_bytes_per_frame`).
    pub telemetry_bytes_per_object: f64,
    /// Uplink bytes of the budget frame (one results message with 4 objects).
    pub telemetry_bytes_per_frame: u64,
    /// Instruction counts per stage.
    pub stages: Vec<(String, u64)>,
    /// `instructions_per_frame / 24 M`.
    pub instructions_vs_budget: f64,
    /// `(ram_bytes + stack_bytes) / 512 KiB`.
    pub ram_vs_budget: f64,
    /// How the numbers were made.
    pub method: &'static str,
}

fn field<'a>(line: &'a str, key: &str) -> Option<&'a str> {
    line.split_whitespace().find_map(|w| w.strip_prefix(key))
}

/// Sizes of `elf`'s sections from `size -A`.
fn sections(elf: &Path) -> Result<Vec<(String, u64)>, crate::Error> {
    let out = Command::new("size")
        .arg("-A")
        .arg(elf)
        .output()
        .map_err(|e| format!("cannot run size (apt-get install -y binutils): {e}"))?;
    if !out.status.success() {
        return Err(format!(
            "size -A {}: {}",
            elf.display(),
            String::from_utf8_lossy(&out.stderr)
        )
        .into());
    }
    Ok(String::from_utf8_lossy(&out.stdout)
        .lines()
        .filter_map(|l| {
            let mut w = l.split_whitespace();
            let (name, size) = (w.next()?, w.next()?.parse().ok()?);
            name.starts_with('.').then(|| (name.to_owned(), size))
        })
        .collect())
}

/// Builds, runs and measures.
///
/// # Errors
/// A message if a build, QEMU or `size` fails or prints something unexpected.
pub fn run(firmware: &Path) -> Result<Budget, crate::Error> {
    let edge = qemu::build(firmware, "edge", None)?;
    let secs = sections(&edge)?;
    let sum = |names: &[&str]| -> u64 {
        secs.iter()
            .filter(|(n, _)| names.contains(&n.as_str()))
            .map(|s| s.1)
            .sum()
    };
    let flash_bytes = sum(&[".vector_table", ".text", ".rodata", ".data"]);
    let ram_bytes = sum(&[".data", ".bss", ".uninit"]);

    let elf = qemu::build(firmware, "pipeline-icount", None)?;
    let out = qemu::run(&elf, true, Duration::from_secs(300))?;
    let mut stages = Vec::new();
    let (mut total, mut calibrated, mut table, mut stack) = (None, None, 0u64, 0u64);
    let mut results = Vec::new();
    for line in out.lines() {
        if let (Some(stage), Some(n)) = (field(line, "stage="), field(line, "instructions=")) {
            let n: u64 = n.parse().map_err(|_| format!("bad line: {line}"))?;
            match stage {
                "frame" => total = Some(n),
                "calibrated_frame" => calibrated = Some(n),
                "calibration_table" => table = n,
                _ => stages.push((stage.to_owned(), n)),
            }
        }
        if let Some(s) = field(line, "stack_bytes=") {
            stack = stack.max(s.parse().map_err(|_| format!("bad line: {line}"))?);
        }
        // Depths from the module; the scores and the alternatives (12.5 m nearer and 8.3 m
        // farther) take typical values, as the benchmark firmware does not report them.
        if line.starts_with("PIPELINE object=") {
            let depth: u32 = field(line, "depth_mm=")
                .and_then(|d| d.parse().ok())
                .unwrap_or(0);
            results.push(ObjectResult {
                instance: results.len() as u16 + 1,
                depth_mm: depth,
                score: Score::new(20.0, true),
                others: [
                    Alternative {
                        offset_cm: -1_250,
                        score: Score::new(15.0, false),
                    },
                    Alternative {
                        offset_cm: 830,
                        score: Score::new(12.5, true),
                    },
                ],
            });
        }
    }
    let instructions_per_frame = total.ok_or(format!("no frame total in:\n{out}"))?;
    let instructions_per_calibrated_frame =
        calibrated.ok_or(format!("no calibrated frame total in:\n{out}"))?;
    stack = stack.max(edge_stack(firmware)?);

    // The uplink of the budget frame: one Results message, measured with 4 objects and with
    // none, so the per-object figure is each object's own share of the wire.
    let frame_bytes = |objects: &[ObjectResult]| -> Result<u64, crate::Error> {
        let mut sender = Sender::new(Key::new(&[0; 32]), Stream::Uplink);
        let mut buf = [0u8; MAX_WIRE];
        let summary = FrameSummary {
            frame: 36_000,
            objects: objects.len() as u8,
            detected: objects.len() as u8,
            peaks: 64,
            exponent: -2,
            busy_us: 90_000,
        };
        let msg = Uplink::Results {
            summary,
            objects: objects.iter().copied().collect(),
        };
        Ok(sender.encode(&msg, &mut buf).map_err(|e| e.to_string())? as u64)
    };
    let bytes = frame_bytes(&results)?;
    let per_object = (bytes - frame_bytes(&[])?) as f64 / results.len().max(1) as f64;
    Ok(Budget {
        flash_bytes,
        ram_bytes,
        stack_bytes: stack,
        instructions_per_frame,
        instructions_per_calibrated_frame,
        calibration_table_instructions: table,
        telemetry_bytes_per_object: per_object,
        telemetry_bytes_per_frame: bytes,
        stages,
        instructions_vs_budget: instructions_per_frame as f64 / INSTRUCTION_BUDGET as f64,
        ram_vs_budget: (ram_bytes + stack) as f64 / RAM_BUDGET as f64,
        method: "size -A (edge); qemu-system-arm -machine mps2-an500 -icount shift=0, CMSDK timer 0 ticks x 40 (pipeline-icount); stack painting",
    })
}

/// Stack high-water mark of the `edge` firmware over a session on a simulated cascade bundle.
fn edge_stack(firmware: &Path) -> Result<u64, crate::Error> {
    use metamoran_process::{Mode, ProcessOptions, Runner, process_streamed};
    use metamoran_sim::{layout::Preset, radar::RadarKind, simulate};
    let dir = std::env::temp_dir().join(format!("metamoran-budget-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    simulate(
        Preset::ParkingLot,
        RadarKind::Cascade,
        4242,
        1,
        &dir,
        &|| (),
    )?;
    let bundle = std::fs::read_dir(&dir)
        .map_err(|e| e.to_string())?
        .filter_map(Result::ok)
        .map(|e| e.path())
        .find(|p| p.is_dir())
        .ok_or("the simulator wrote no bundle")?;
    let options = ProcessOptions {
        runner: Runner::Qemu {
            firmware: firmware.to_owned(),
            key_file: metamoran_edge::keys::checkout_key(firmware)?,
        },
        ..ProcessOptions::mode(Mode::Metamoran)
    };
    let (_, log) = process_streamed(&bundle, &options, |_| Ok(()))?;
    let _ = std::fs::remove_dir_all(&dir);
    let stack = log
        .map(|l| u64::from(l.health.stack_bytes))
        .filter(|&s| s > 0)
        .ok_or("the edge firmware did not report its stack in its Health message")?;
    Ok(stack)
}

impl std::fmt::Display for Budget {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(f, "Runner budgets ({})", self.method)?;
        writeln!(
            f,
            "flash        {:>10} B  ({:.1} % of 2 MiB)",
            self.flash_bytes,
            100.0 * self.flash_bytes as f64 / FLASH_BUDGET as f64
        )?;
        writeln!(f, "static RAM   {:>10} B", self.ram_bytes)?;
        writeln!(
            f,
            "stack        {:>10} B  (RAM + stack = {:.1} % of 512 KiB)",
            self.stack_bytes,
            100.0 * self.ram_vs_budget
        )?;
        writeln!(
            f,
            "instructions {:>10}    per 4-object cascade frame = {:.3}× the 24 M budget",
            self.instructions_per_frame, self.instructions_vs_budget
        )?;
        writeln!(
            f,
            "calibrated   {:>10}    the same frame from an imperfect board, calibrated = {:.3}× the budget (table: {} once per configuration)",
            self.instructions_per_calibrated_frame,
            self.instructions_per_calibrated_frame as f64 / INSTRUCTION_BUDGET as f64,
            self.calibration_table_instructions
        )?;
        for (s, n) in &self.stages {
            writeln!(f, "  {s:<32} {n:>10}")?;
        }
        writeln!(
            f,
            "telemetry    {:>10.1} B per object, {} B per frame",
            self.telemetry_bytes_per_object, self.telemetry_bytes_per_frame
        )
    }
}
