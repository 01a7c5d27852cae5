//! Clutter: removal of what does not move before Doppler processing, and successive
//! interference cancellation of strong reflectors outside an object's span.

pub mod peaks;
pub mod sic;
mod static_removal;

pub use static_removal::remove_mean;
