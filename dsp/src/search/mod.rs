//! Search: the camera-guided depth search of Metamoran (Sec. III-A, Algorithm 1).
//!
//! The camera gives an object's contour: for each point, its azimuth and its range relative to
//! the object's closest point ([`Contour`]). The radar depth `d*` is where that contour, shifted so
//! its closest point sits at `d`, best matches the radar data.
//!
//! **The carrier phase of each contour point is unknown.** Eq. 1 synthesizes
//! `α·exp(j4πD/λ)·exp(j2πDn/D_max)`, but the monocular ranges `D` are decimetres to metres off
//! while λ ≈ 3.9 mm, so the phase term `4πD/λ` of every point is effectively random: a coherent
//! template would add the points with random phases and match nothing. We therefore treat each
//! point's complex amplitude as unknown; the generalized likelihood test then maximizes over
//! each phase separately, which gives the non-coherent matched filter
//!
//! `P(d) = Σᵢ |Bᵢ(d + relᵢ)|²`,
//!
//! where `Bᵢ(r)` is the radar signal beamformed toward point i's azimuth and matched-filtered at
//! range `r` (the range spectrum at a fractional bin). The shape still matters: a depth is only
//! good if energy sits at every contour point's range *and* azimuth, which a clutter peak at one
//! place does not provide.
//!
//! [`depth::brute_force`] evaluates this on raw samples for every candidate depth, as the paper's
//! `O(D·N²)` matched filter; [`depth::coarse_to_fine`] evaluates the same function from the
//! fixed-point range spectra, first on the bin grid, then by Dirichlet interpolation of the
//! zero-padded spectrum on a fine grid around the best coarse candidates.

mod contour;
pub mod depth;
pub mod survival;

pub use contour::{Contour, ContourPoint, MAX_CONTOUR};
