//! Clutter: removal of what does not move, before Doppler processing.

mod static_removal;

pub use static_removal::remove_mean;
