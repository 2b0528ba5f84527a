//! A saved FMU state as the host holds it: the FMU's own pointer in process, or the address a host
//! process knows it by for an isolated instance.

use crate::fmi2::types::Fmi2FmuState;

/// An FMU state saved by fmi2GetFMUstate or restored by fmi2DeSerializeFMUstate. Free it with
/// [`Instance::free_state`] on the instance that made it.
#[derive(Debug)]
pub struct SavedState(pub(super) Fmi2FmuState);

// SAFETY: a saved state is only handed back to the instance that made it, which is Send.
unsafe impl Send for SavedState {}

impl SavedState {
    /// A state an isolated instance's host made, by the address the host knows it by.
    pub(crate) fn from_handle(handle: u64) -> Self {
        Self(handle as usize as Fmi2FmuState)
    }

    pub(crate) fn handle(&self) -> u64 {
        self.0 as usize as u64
    }
}
