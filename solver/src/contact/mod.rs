//! Contact (thesis chapters 6 and 7).

pub mod broad_phase;
pub mod ccd;
pub mod detection;
pub mod gauss_seidel;
