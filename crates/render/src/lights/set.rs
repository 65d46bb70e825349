//! The scene's lights and how one is chosen: by power over all lights, uniformly over the
//! scene's light objects, or every light object in turn ([`LightSelection`]).
//!
//! A light *object* is what the scene file declares: a point light, or an emitting shape.
//! An emitting mesh is one object made of one [`AreaLight`] per triangle; within an object
//! a light is chosen by power (for a mesh: by triangle area).

use super::{AreaLight, Light};
use penumbra_core::lanes::Real;
use penumbra_core::Distribution1D;
use std::ops::Range;

/// How the direct-lighting estimators choose a light for each shadow ray.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LightSelection {
    /// Every light object gets its own shadow rays (the sum over lights of the course).
    All,
    /// One light per shadow ray, with probability proportional to its power.
    #[default]
    Power,
    /// One light object per shadow ray, each equally likely.
    Uniform,
}

impl LightSelection {
    pub const NAMES: [&'static str; 3] = ["power", "uniform", "all"];

    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "all" => Some(LightSelection::All),
            "power" => Some(LightSelection::Power),
            "uniform" => Some(LightSelection::Uniform),
            _ => None,
        }
    }
}

/// One light object: a range of [`LightSet::lights`] and how to pick among them.
#[derive(Clone, Debug)]
struct Group {
    lights: Range<u32>,
    /// By power within the group; `None` when nothing in it emits.
    within: Option<Distribution1D>,
}

/// All lights of a scene, with the distributions that choose among them.
#[derive(Clone, Debug, Default)]
pub struct LightSet {
    lights: Vec<Light>,
    groups: Vec<Group>,
    group_of: Vec<u32>,
    /// Over every light, by power.
    by_power: Option<Distribution1D>,
    /// The first light of each scene object that emits (objects are numbered by the geometry).
    object_lights: Vec<Option<u32>>,
}

/// Collects light objects in order.
#[derive(Default)]
pub struct LightSetBuilder {
    set: LightSet,
    scene_radius: f32,
}

impl LightSetBuilder {
    /// `scene_radius` sizes the power of directional lights.
    pub fn new(scene_radius: f32) -> Self {
        LightSetBuilder {
            set: LightSet::default(),
            scene_radius,
        }
    }

    /// Adds a light that is not part of the geometry (point, spot, directional,
    /// environment); returns its index.
    pub fn add(&mut self, light: Light) -> u32 {
        self.add_group(vec![light]);
        self.set.lights.len() as u32 - 1
    }

    /// Adds the area lights of scene object `object` (one per triangle for a mesh).
    pub fn add_emitter(&mut self, object: u32, lights: Vec<AreaLight>) {
        let first = self.set.lights.len() as u32;
        let objects = &mut self.set.object_lights;
        if objects.len() <= object as usize {
            objects.resize(object as usize + 1, None);
        }
        objects[object as usize] = Some(first);
        self.add_group(lights.into_iter().map(Light::Area).collect());
    }

    fn add_group(&mut self, lights: Vec<Light>) {
        let set = &mut self.set;
        let start = set.lights.len() as u32;
        let group = set.groups.len() as u32;
        let within = Distribution1D::new(lights.iter().map(|l| l.power(self.scene_radius)));
        set.group_of.extend(std::iter::repeat_n(group, lights.len()));
        set.lights.extend(lights);
        set.groups.push(Group {
            lights: start..set.lights.len() as u32,
            within,
        });
    }

    pub fn build(mut self) -> LightSet {
        let r = self.scene_radius;
        self.set.by_power = Distribution1D::new(self.set.lights.iter().map(|l| l.power(r)));
        self.set
    }
}

impl LightSet {
    pub fn lights(&self) -> &[Light] {
        &self.lights
    }

    pub fn len(&self) -> usize {
        self.lights.len()
    }

    pub fn is_empty(&self) -> bool {
        self.lights.is_empty()
    }

    /// Number of light objects.
    pub fn groups(&self) -> usize {
        self.groups.len()
    }

    /// The lights of object `group`.
    pub fn group_lights(&self, group: usize) -> Range<u32> {
        self.groups[group].lights.clone()
    }

    /// Whether scene object `object` emits (then every triangle of it has its own light).
    pub fn emits(&self, object: u32) -> bool {
        self.object_lights.get(object as usize).is_some_and(Option::is_some)
    }

    /// The area light of `triangle` (0 for analytic shapes) of scene object `object`, if it emits.
    pub fn emitter_of(&self, object: u32, triangle: u32) -> Option<(u32, &AreaLight)> {
        let first = (*self.object_lights.get(object as usize)?)?;
        let index = first + triangle;
        debug_assert!(
            self.group_of.get(index as usize) == self.group_of.get(first as usize),
            "triangle {triangle} of object {object} has no light of its own"
        );
        match self.lights.get(index as usize) {
            Some(Light::Area(a)) => Some((index, a)),
            _ => None,
        }
    }

    /// A light of object `group` by power within the object, and its probability.
    pub fn pick_in_group(&self, group: usize, u: f32) -> Option<(u32, f32)> {
        let g = &self.groups[group];
        let (i, pmf, _) = g.within.as_ref()?.sample(u);
        Some((g.lights.start + i as u32, pmf))
    }

    /// A light chosen by `selection` and its probability. [`LightSelection::All`] is meant
    /// for [`LightSet::pick_in_group`], object by object; here it picks by power. The
    /// one-lane instance of [`LightSet::pick_lanes`].
    pub fn pick(&self, selection: LightSelection, u: f32) -> Option<(u32, f32)> {
        let (i, pmf) = self.pick_lanes(selection, u);
        (i >= 0.0).then_some((i as u32, pmf))
    }

    /// [`LightSet::pick`] per lane: each lane's light (its index as a float, exact below
    /// 2^24; -1 where there is none) and its probability. By power in lanes
    /// ([`Distribution1D::sample_lanes`]); uniformly over objects, each lane's pick within
    /// its object one by one.
    #[inline(always)]
    pub fn pick_lanes<R: Real>(&self, selection: LightSelection, u: R) -> (R, R) {
        let none = (R::splat(-1.0), R::splat(0.0));
        match selection {
            LightSelection::Power | LightSelection::All => match &self.by_power {
                Some(d) => {
                    let (i, pmf, _) = d.sample_lanes(u);
                    (i, pmf)
                }
                None => none,
            },
            LightSelection::Uniform => {
                let [i, pmf] = R::map_lanes([u], |_, [u]| match self.pick_uniformly(u) {
                    Some((i, pmf)) => [i as f32, pmf],
                    None => [-1.0, 0.0],
                });
                (i, pmf)
            }
        }
    }

    /// [`LightSelection::Uniform`]'s pick: an object uniformly, then a light within it.
    fn pick_uniformly(&self, u: f32) -> Option<(u32, f32)> {
        let n = self.groups.len();
        if n == 0 {
            return None;
        }
        let g = ((u * n as f32) as usize).min(n - 1);
        let rest = (u * n as f32 - g as f32).clamp(0.0, penumbra_core::samplers::ONE_MINUS_EPSILON);
        let (i, pmf) = self.pick_in_group(g, rest)?;
        Some((i, pmf / n as f32))
    }

    /// The probability that `selection` picks light `index` for one shadow ray (for
    /// [`LightSelection::All`]: within its object).
    pub fn pmf(&self, selection: LightSelection, index: u32) -> f32 {
        let g = &self.groups[self.group_of[index as usize] as usize];
        let within = || {
            g.within
                .as_ref()
                .map_or(0.0, |d| d.pmf((index - g.lights.start) as usize))
        };
        match selection {
            LightSelection::All => within(),
            LightSelection::Power => self.by_power.as_ref().map_or(0.0, |d| d.pmf(index as usize)),
            LightSelection::Uniform => within() / self.groups.len() as f32,
        }
    }
}
