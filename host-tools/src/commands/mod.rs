//! One module per subcommand, each an `Args` (clap) and a `run`; [`args`] holds the options
//! several commands share and the command-line names of library enums.

pub mod alerts;
pub mod args;
pub mod bench;
pub mod calibrate;
pub mod dca1000_emulate;
pub mod demo;
pub mod demo_capture;
pub mod eval;
pub mod inspect;
pub mod map;
pub mod odometry;
pub mod process;
pub mod progress;
pub mod provision;
pub mod record;
pub mod serve;
pub mod simulate;
pub mod site;
pub mod summarize;

/// What a command returns: any library error, shown by `main` as `error: …`.
pub type Result = std::result::Result<(), metamoran::Error>;

/// Prints `value` as pretty JSON, or through its `Display` (the report's table).
///
/// # Errors
/// If `value` cannot be serialized.
pub fn print<T: serde::Serialize + std::fmt::Display>(value: &T, json: bool) -> Result {
    if json {
        print_json(value)
    } else {
        print!("{value}");
        Ok(())
    }
}

/// Prints `value` as pretty JSON.
///
/// # Errors
/// If `value` cannot be serialized.
pub fn print_json<T: serde::Serialize>(value: &T) -> Result {
    println!("{}", serde_json::to_string_pretty(value)?);
    Ok(())
}
