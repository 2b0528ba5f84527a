//! The FMU side of FMI 2.0: what a model implements ([`slave::Slave`]), its errors ([`error`]), the
//! variable tables generated from modelDescription/*.xml ([`variables`]), and the export adapter
//! ([`export`]) behind the `export_fmu!` macro that emits the C symbols.

pub mod error;
pub mod export;
pub mod slave;
pub mod variables;

/// The interface items of a [`slave::Slave`] impl, taken from the generated `models::<name>` module
/// the invoking file imports as `xml` (identifier, GUID, XML text, variable table and lookup).
#[macro_export]
macro_rules! slave_interface_from_xml {
    () => {
        const MODEL_IDENTIFIER: &'static str = xml::MODEL_IDENTIFIER;
        const GUID: &'static str = xml::GUID;
        const MODEL_DESCRIPTION_XML: &'static str = xml::MODEL_DESCRIPTION_XML;
        const VARIABLES: &'static [$crate::fmi2::fmu::variables::Variable] = xml::VARIABLES;

        #[inline]
        fn variable(
            ty: $crate::fmi2::fmu::variables::VarType,
            r: u32,
        ) -> Option<&'static $crate::fmi2::fmu::variables::Variable> {
            xml::variable(ty, r)
        }
    };
}

/// Emits the 34 `fmi2*` symbols of a Co-Simulation FMU for a [`slave::Slave`] type, plus
/// `windrive_model_description`, which returns the exact modelDescription.xml (with this build's
/// GUID) so `windrive pack` ships the XML the binary was built from.
#[macro_export]
macro_rules! export_fmu {
    ($slave:ty) => {
        mod fmi2_exports {
            #![allow(non_snake_case, clippy::missing_safety_doc)]
            use super::*;
            use std::ffi::{c_char, c_int};
            use $crate::fmi2::fmu::export as e;
            use $crate::fmi2::types::*;
            type S = $slave;

            #[unsafe(no_mangle)]
            pub extern "C" fn windrive_model_description() -> *const c_char {
                static XML: std::sync::OnceLock<std::ffi::CString> = std::sync::OnceLock::new();
                XML.get_or_init(|| {
                    std::ffi::CString::new(<S as $crate::fmi2::fmu::slave::Slave>::MODEL_DESCRIPTION_XML)
                        .unwrap_or_default()
                })
                .as_ptr()
            }
            #[unsafe(no_mangle)]
            pub extern "C" fn fmi2GetTypesPlatform() -> *const c_char {
                TYPES_PLATFORM.as_ptr()
            }
            #[unsafe(no_mangle)]
            pub extern "C" fn fmi2GetVersion() -> *const c_char {
                VERSION.as_ptr()
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetDebugLogging(
                c: Fmi2Component,
                on: Fmi2Boolean,
                n: usize,
                cats: *const Fmi2String,
            ) -> Fmi2Status {
                unsafe { e::set_debug_logging::<S>(c, on, n, cats) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2Instantiate(
                name: Fmi2String,
                kind: c_int,
                guid: Fmi2String,
                resources: Fmi2String,
                functions: *const Fmi2CallbackFunctions,
                visible: Fmi2Boolean,
                logging_on: Fmi2Boolean,
            ) -> Fmi2Component {
                unsafe { e::instantiate::<S>(name, kind, guid, resources, functions, visible, logging_on) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2FreeInstance(c: Fmi2Component) {
                unsafe { e::free_instance::<S>(c) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetupExperiment(
                c: Fmi2Component,
                tol_defined: Fmi2Boolean,
                tol: f64,
                start: f64,
                stop_defined: Fmi2Boolean,
                stop: f64,
            ) -> Fmi2Status {
                unsafe { e::setup_experiment::<S>(c, tol_defined, tol, start, stop_defined, stop) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2EnterInitializationMode(c: Fmi2Component) -> Fmi2Status {
                unsafe { e::enter_initialization_mode::<S>(c) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2ExitInitializationMode(c: Fmi2Component) -> Fmi2Status {
                unsafe { e::exit_initialization_mode::<S>(c) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2Terminate(c: Fmi2Component) -> Fmi2Status {
                unsafe { e::terminate::<S>(c) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2Reset(c: Fmi2Component) -> Fmi2Status {
                unsafe { e::reset::<S>(c) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetReal(
                c: Fmi2Component,
                vr: *const Fmi2ValueReference,
                n: usize,
                v: *mut f64,
            ) -> Fmi2Status {
                unsafe { e::get_real::<S>(c, vr, n, v) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetInteger(
                c: Fmi2Component,
                vr: *const Fmi2ValueReference,
                n: usize,
                v: *mut c_int,
            ) -> Fmi2Status {
                unsafe { e::get_integer::<S>(c, vr, n, v) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetBoolean(
                c: Fmi2Component,
                vr: *const Fmi2ValueReference,
                n: usize,
                v: *mut Fmi2Boolean,
            ) -> Fmi2Status {
                unsafe { e::get_boolean::<S>(c, vr, n, v) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetString(
                c: Fmi2Component,
                vr: *const Fmi2ValueReference,
                n: usize,
                v: *mut Fmi2String,
            ) -> Fmi2Status {
                unsafe { e::get_string::<S>(c, vr, n, v) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetReal(
                c: Fmi2Component,
                vr: *const Fmi2ValueReference,
                n: usize,
                v: *const f64,
            ) -> Fmi2Status {
                unsafe { e::set_real::<S>(c, vr, n, v) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetInteger(
                c: Fmi2Component,
                vr: *const Fmi2ValueReference,
                n: usize,
                v: *const c_int,
            ) -> Fmi2Status {
                unsafe { e::set_integer::<S>(c, vr, n, v) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetBoolean(
                c: Fmi2Component,
                vr: *const Fmi2ValueReference,
                n: usize,
                v: *const Fmi2Boolean,
            ) -> Fmi2Status {
                unsafe { e::set_boolean::<S>(c, vr, n, v) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetString(
                c: Fmi2Component,
                vr: *const Fmi2ValueReference,
                n: usize,
                v: *const Fmi2String,
            ) -> Fmi2Status {
                unsafe { e::set_string::<S>(c, vr, n, v) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetFMUstate(c: Fmi2Component, s: *mut Fmi2FmuState) -> Fmi2Status {
                unsafe { e::get_fmu_state::<S>(c, s) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetFMUstate(c: Fmi2Component, s: Fmi2FmuState) -> Fmi2Status {
                unsafe { e::set_fmu_state::<S>(c, s) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2FreeFMUstate(c: Fmi2Component, s: *mut Fmi2FmuState) -> Fmi2Status {
                unsafe { e::free_fmu_state::<S>(c, s) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
                c: Fmi2Component,
                s: Fmi2FmuState,
                size: *mut usize,
            ) -> Fmi2Status {
                unsafe { e::serialized_fmu_state_size::<S>(c, s, size) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SerializeFMUstate(
                c: Fmi2Component,
                s: Fmi2FmuState,
                bytes: *mut Fmi2Byte,
                size: usize,
            ) -> Fmi2Status {
                unsafe { e::serialize_fmu_state::<S>(c, s, bytes, size) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
                c: Fmi2Component,
                bytes: *const Fmi2Byte,
                size: usize,
                s: *mut Fmi2FmuState,
            ) -> Fmi2Status {
                unsafe { e::deserialize_fmu_state::<S>(c, bytes, size, s) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
                c: Fmi2Component,
                _u: *const Fmi2ValueReference,
                _nu: usize,
                _z: *const Fmi2ValueReference,
                _nz: usize,
                _du: *const f64,
                _dz: *mut f64,
            ) -> Fmi2Status {
                unsafe { e::get_directional_derivative::<S>(c) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
                c: Fmi2Component,
                vr: *const Fmi2ValueReference,
                n: usize,
                order: *const Fmi2Integer,
                v: *const f64,
            ) -> Fmi2Status {
                unsafe { e::set_real_input_derivatives::<S>(c, vr, n, order, v) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
                c: Fmi2Component,
                _vr: *const Fmi2ValueReference,
                _n: usize,
                _order: *const Fmi2Integer,
                _v: *mut f64,
            ) -> Fmi2Status {
                unsafe { e::get_real_output_derivatives::<S>(c) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2DoStep(c: Fmi2Component, t: f64, h: f64, no_prior: Fmi2Boolean) -> Fmi2Status {
                unsafe { e::do_step::<S>(c, t, h, no_prior) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2CancelStep(c: Fmi2Component) -> Fmi2Status {
                unsafe { e::cancel_step::<S>(c) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetStatus(c: Fmi2Component, k: c_int, v: *mut c_int) -> Fmi2Status {
                unsafe { e::get_status::<S>(c, k, v) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetRealStatus(c: Fmi2Component, k: c_int, v: *mut f64) -> Fmi2Status {
                unsafe { e::get_real_status::<S>(c, k, v) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetIntegerStatus(c: Fmi2Component, k: c_int, v: *mut c_int) -> Fmi2Status {
                unsafe { e::get_integer_status::<S>(c, k, v) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetBooleanStatus(
                c: Fmi2Component,
                k: c_int,
                v: *mut Fmi2Boolean,
            ) -> Fmi2Status {
                unsafe { e::get_boolean_status::<S>(c, k, v) }
            }
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetStringStatus(c: Fmi2Component, k: c_int, v: *mut Fmi2String) -> Fmi2Status {
                unsafe { e::get_string_status::<S>(c, k, v) }
            }
        }
    };
}
