//! Every element's load at once, for a reader of many outputs (a recorder's row): the elements' numbers
//! packed side by side, so that a row costs a tight loop instead of a walk through each [`Element`]'s
//! vectors and options. The arithmetic is [`TorsionalModel`]'s `element_load`, operation for operation,
//! so the loads are its bits (tests/it/read_plan.rs compares them with the model's `element_output` and
//! `stored_energy`).

use super::{Element, ElementLoad, TorsionalModel};

/// An element on `N` DOFs (a shaft or a parallel mesh: two; a sun–planet mesh with its carrier: three)
/// with the numbers its load needs.
#[derive(Debug, Clone, Copy)]
struct Packed<const N: usize> {
    element: usize,
    dofs: [usize; N],
    coeffs: [f64; N],
    ratios: [f64; N],
    stiffness: f64,
    damping: f64,
    half_backlash: f64,
    boundary: f64,
    /// The stiffness follows the mesh's roll: asked of the element itself.
    varies: bool,
}

impl<const N: usize> Packed<N> {
    fn of(i: usize, e: &Element, dofs: usize) -> Option<Self> {
        let (coeffs, ratios) = (&e.coeffs, &e.ratios);
        if coeffs.len() != N || ratios.len() != N || coeffs.iter().any(|&(d, _)| d >= dofs) {
            return None;
        }
        Some(Self {
            element: i,
            dofs: std::array::from_fn(|j| coeffs[j].0),
            coeffs: std::array::from_fn(|j| coeffs[j].1),
            ratios: std::array::from_fn(|j| ratios[j]),
            stiffness: e.stiffness,
            damping: e.damping,
            half_backlash: e.half_backlash,
            boundary: e.boundary,
            varies: e.variation.is_some(),
        })
    }

    /// Σ g_j (x_{d_j} − r_j x_0), summed in the element's order ([`Element::deflection`]'s).
    #[inline(always)]
    fn deflection(&self, x: &[f64], x0: f64) -> f64 {
        let term = |j: usize| self.coeffs[j] * (x[self.dofs[j]] - self.ratios[j] * x0);
        (1..N).fold(term(0), |sum, j| sum + term(j))
    }

    #[inline(always)]
    fn load(
        &self,
        model: &TorsionalModel,
        (q, v): (&[f64], &[f64]),
        (q0, v0): (f64, f64),
        boundary: (f64, f64),
    ) -> ElementLoad {
        let (angle, speed) = (self.boundary * boundary.0, self.boundary * boundary.1);
        let k = if self.varies {
            model.elements[self.element].stiffness_at(q)
        } else {
            self.stiffness
        };
        let contact = Element::contact_of(self.half_backlash, self.deflection(q, q0) + angle);
        ElementLoad {
            force: Element::spring_damper(k, self.damping, contact, self.deflection(v, v0) + speed),
            energy: 0.5 * k * contact.0 * contact.0,
        }
    }
}

/// Where an element's numbers are in an [`ElementTable`].
#[derive(Debug, Clone, Copy)]
enum Slot {
    Pair(usize),
    Triple(usize),
    /// Read through the element itself.
    Other,
}

/// The loads of a model's elements, those on two and three DOFs packed, the rest read through the element.
#[derive(Debug, Clone, Default)]
pub struct ElementTable {
    pairs: Vec<Packed<2>>,
    triples: Vec<Packed<3>>,
    others: Vec<usize>,
    slots: Vec<Slot>,
}

impl ElementTable {
    pub fn new(model: &TorsionalModel) -> Self {
        let dofs = model.mass.len();
        let mut table = Self::default();
        for (i, e) in model.elements.iter().enumerate() {
            let slot = if let Some(p) = Packed::of(i, e, dofs) {
                table.pairs.push(p);
                Slot::Pair(table.pairs.len() - 1)
            } else if let Some(p) = Packed::of(i, e, dofs) {
                table.triples.push(p);
                Slot::Triple(table.triples.len() - 1)
            } else {
                table.others.push(i);
                Slot::Other
            };
            table.slots.push(slot);
        }
        table
    }

    /// Element `e`'s force and elastic energy at (q, v) and the cut's `boundary`: `element_load`'s
    /// values, for the `model` this table was made of.
    pub fn load(&self, model: &TorsionalModel, e: usize, q: &[f64], v: &[f64], boundary: (f64, f64)) -> ElementLoad {
        let first = || (q.first().copied().unwrap_or(0.0), v.first().copied().unwrap_or(0.0));
        match self.slots[e] {
            Slot::Pair(i) => self.pairs[i].load(model, (q, v), first(), boundary),
            Slot::Triple(i) => self.triples[i].load(model, (q, v), first(), boundary),
            Slot::Other => model.element_load_of(e, q, v, boundary),
        }
    }

    /// Every element's force and elastic energy at (q, v) and the cut's `boundary` into `out`, one entry
    /// per element: `element_load`'s values, for the `model` this table was made of.
    pub fn loads(
        &self,
        model: &TorsionalModel,
        q: &[f64],
        v: &[f64],
        boundary: (f64, f64),
        out: &mut Vec<ElementLoad>,
    ) {
        // the pairs, the triples and the rest in loops of their own: one loop over the slots, a match per
        // element, cost the simulation thread 133.5 -> 138.6 M instructions over 10 s of c-shutdown-spring
        // with every output recorded (callgrind, 2026-12-01)
        out.clear();
        out.resize(self.slots.len(), ElementLoad::default());
        // DOF 0's angle and speed: the rigid rotation the deflections are taken from
        let first = (q.first().copied().unwrap_or(0.0), v.first().copied().unwrap_or(0.0));
        for p in &self.pairs {
            out[p.element] = p.load(model, (q, v), first, boundary);
        }
        for p in &self.triples {
            out[p.element] = p.load(model, (q, v), first, boundary);
        }
        for &i in &self.others {
            out[i] = model.element_load_of(i, q, v, boundary);
        }
    }
}
