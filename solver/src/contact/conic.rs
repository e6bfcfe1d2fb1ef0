//! Contact as a conic program solved by Clarabel (FORMULATION section 4, "Conic solver").
