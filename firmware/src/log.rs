//! The module's event log: `defmt` on the target (binary frames over semihosting, decoded on the
//! host by `defmt-print -e ELF`), nothing on the host, where tests read the counters instead.
//!
//! Every counted error of the loop is also logged here, so a person watching the module sees
//! each event as it happens and the host sees the totals in [`metamoran_dsp::wire::Health`].

/// Logs an event at `info` level (format string and arguments as in `defmt::info!`).
#[macro_export]
macro_rules! info {
    ($fmt:literal $(, $arg:expr)* $(,)?) => {{
        #[cfg(target_os = "none")]
        defmt::info!($fmt $(, $arg)*);
        #[cfg(not(target_os = "none"))]
        { $(let _ = &$arg;)* }
    }};
}

/// Logs a counted error at `warn` level (format string and arguments as in `defmt::warn!`).
#[macro_export]
macro_rules! warn {
    ($fmt:literal $(, $arg:expr)* $(,)?) => {{
        #[cfg(target_os = "none")]
        defmt::warn!($fmt $(, $arg)*);
        #[cfg(not(target_os = "none"))]
        { $(let _ = &$arg;)* }
    }};
}
