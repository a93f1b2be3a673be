//! Nothing to run: cargo compiles every dependency of a package whether its code uses it or not,
//! so this empty binary measures the cold build of the workspace's heavy dependencies alone
//! (see `Cargo.toml`).
fn main() {}
