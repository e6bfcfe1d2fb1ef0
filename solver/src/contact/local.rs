//! One-contact solvers: the local step of nonlinear Gauss-Seidel.
