//! modelDescription.xml of an FMI 2.0 FMU, read with quick-xml + serde: the parts a master needs.

use serde::Deserialize;

#[derive(Debug, Clone, Deserialize)]
pub struct ModelDescription {
    #[serde(rename = "@fmiVersion")]
    pub fmi_version: String,
    #[serde(rename = "@modelName")]
    pub model_name: String,
    #[serde(rename = "@guid")]
    pub guid: String,
    #[serde(rename = "CoSimulation")]
    pub co_simulation: Option<CoSimulation>,
    #[serde(rename = "DefaultExperiment")]
    pub default_experiment: Option<DefaultExperiment>,
    #[serde(rename = "ModelVariables")]
    pub model_variables: ModelVariables,
    #[serde(rename = "ModelStructure", default)]
    pub model_structure: ModelStructure,
}

#[derive(Debug, Clone, Deserialize, Default)]
pub struct ModelStructure {
    #[serde(rename = "Outputs", default)]
    pub outputs: UnknownList,
}

#[derive(Debug, Clone, Deserialize, Default)]
pub struct UnknownList {
    #[serde(rename = "Unknown", default)]
    pub unknowns: Vec<Unknown>,
}

/// One row of ModelStructure: a variable (1-based index into ModelVariables) and what it depends on.
#[derive(Debug, Clone, Deserialize)]
pub struct Unknown {
    #[serde(rename = "@index")]
    pub index: usize,
    /// Space-separated 1-based indices; absent means "may depend on every input" (FMI 2.0 §2.2.8).
    #[serde(rename = "@dependencies")]
    pub dependencies: Option<String>,
}

#[derive(Debug, Clone, Deserialize)]
pub struct CoSimulation {
    #[serde(rename = "@modelIdentifier")]
    pub model_identifier: String,
    #[serde(rename = "@canHandleVariableCommunicationStepSize", default)]
    pub can_handle_variable_step: bool,
    #[serde(rename = "@canInterpolateInputs", default)]
    pub can_interpolate_inputs: bool,
    #[serde(rename = "@canGetAndSetFMUstate", default)]
    pub can_get_and_set_fmu_state: bool,
    #[serde(rename = "@canSerializeFMUstate", default)]
    pub can_serialize_fmu_state: bool,
    #[serde(rename = "@maxOutputDerivativeOrder", default)]
    pub max_output_derivative_order: u32,
}

#[derive(Debug, Clone, Deserialize)]
pub struct DefaultExperiment {
    #[serde(rename = "@startTime")]
    pub start_time: Option<f64>,
    #[serde(rename = "@stopTime")]
    pub stop_time: Option<f64>,
    #[serde(rename = "@stepSize")]
    pub step_size: Option<f64>,
}

#[derive(Debug, Clone, Deserialize, Default)]
pub struct ModelVariables {
    #[serde(rename = "ScalarVariable", default)]
    pub variables: Vec<ScalarVariable>,
}

#[derive(Debug, Clone, Deserialize)]
pub struct TypeAttributes {
    #[serde(rename = "@start")]
    pub start: Option<String>,
    #[serde(rename = "@unit")]
    pub unit: Option<String>,
}

#[derive(Debug, Clone, Deserialize)]
pub struct ScalarVariable {
    #[serde(rename = "@name")]
    pub name: String,
    #[serde(rename = "@valueReference")]
    pub value_reference: u32,
    #[serde(rename = "@causality", default = "local")]
    pub causality: String,
    #[serde(rename = "@variability", default = "continuous")]
    pub variability: String,
    #[serde(rename = "@initial")]
    pub initial: Option<String>,
    #[serde(rename = "@description")]
    pub description: Option<String>,
    #[serde(rename = "@declaredType")]
    pub declared_type: Option<String>,
    #[serde(rename = "Real")]
    pub real: Option<TypeAttributes>,
    #[serde(rename = "Integer")]
    pub integer: Option<TypeAttributes>,
    #[serde(rename = "Boolean")]
    pub boolean: Option<TypeAttributes>,
    #[serde(rename = "String")]
    pub string: Option<TypeAttributes>,
    #[serde(rename = "Enumeration")]
    pub enumeration: Option<TypeAttributes>,
}

fn local() -> String {
    "local".into()
}
fn continuous() -> String {
    "continuous".into()
}

impl ScalarVariable {
    pub fn type_name(&self) -> &'static str {
        if self.real.is_some() {
            "Real"
        } else if self.integer.is_some() {
            "Integer"
        } else if self.boolean.is_some() {
            "Boolean"
        } else if self.string.is_some() {
            "String"
        } else {
            "Enumeration"
        }
    }

    pub fn attributes(&self) -> Option<&TypeAttributes> {
        self.real
            .as_ref()
            .or(self.integer.as_ref())
            .or(self.boolean.as_ref())
            .or(self.string.as_ref())
            .or(self.enumeration.as_ref())
    }
}

impl ModelDescription {
    pub fn parse(xml: &str) -> Result<Self, quick_xml::DeError> {
        quick_xml::de::from_str(xml)
    }

    pub fn variable(&self, name: &str) -> Option<&ScalarVariable> {
        self.model_variables.variables.iter().find(|v| v.name == name)
    }

    /// For each output (by name): the inputs it depends on directly, and whether that list was
    /// declared (`Some`) or left open, which the standard reads as "every input" (`None`).
    pub fn output_dependencies(&self) -> Vec<(&str, Option<Vec<&str>>)> {
        let vars = &self.model_variables.variables;
        let name_of = |i: usize| vars.get(i.wrapping_sub(1)).map(|v| v.name.as_str());
        self.model_structure
            .outputs
            .unknowns
            .iter()
            .filter_map(|u| {
                let out = name_of(u.index)?;
                let deps = u.dependencies.as_ref().map(|d| {
                    d.split_whitespace()
                        .filter_map(|t| t.parse().ok().and_then(name_of))
                        .filter(|n| self.variable(n).is_some_and(|v| v.causality == "input"))
                        .collect()
                });
                Some((out, deps))
            })
            .collect()
    }
}
