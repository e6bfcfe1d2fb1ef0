//! Contact (thesis chapters 6 and 7).

pub mod ccd;
pub mod gauss_seidel;
