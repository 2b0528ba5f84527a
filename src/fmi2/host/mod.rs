//! The host side of FMI 2.0, what the master and the command line use: FMU archives unpacked
//! ([`archive`]), model descriptions read ([`description`]), instances driven in process
//! ([`import`]) or each in a process of its own ([`isolate`], whose child processes run [`serve`]),
//! their errors ([`error`]) and saved states ([`state`]).
//!
//! Imports run one way: `serve` → `import` → `isolate` → `error`, `state`; nothing here imports
//! the FMU side but the shared C types.

pub mod archive;
pub mod description;
pub mod error;
pub mod import;
pub mod isolate;
pub mod serve;
pub mod state;
