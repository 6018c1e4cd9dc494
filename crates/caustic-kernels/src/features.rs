//! The classic ray tracer's feature switches: `caustic render --feature NAME=VALUE`. Each
//! feature becomes a pipeline override constant of the kernel (`shaders/classic/features.wgsl`),
//! so a render compiles only the features it uses: by default those its scene uses
//! ([`crate::classic::scene_features`]), and the command line forces any on or off. The
//! table [`FEATURES`] is the one list of names, values, defaults and costs (docs/FEATURES.md
//! shows it).

/// `CLASSIC_FEATURES` bit: shadow rays.
pub const FEATURE_SHADOWS: u32 = 1;
/// `CLASSIC_FEATURES` bit: extended lights sampled at `light-samples` points per pass.
pub const FEATURE_SOFT_SHADOWS: u32 = 2;
/// `CLASSIC_FEATURES` bit: shadow rays pass transparent surfaces, tinted.
pub const FEATURE_LIGHT_TRANSPARENCY: u32 = 4;
/// `CLASSIC_FEATURES` bit: recursive mirror reflection.
pub const FEATURE_REFLECTION: u32 = 8;
/// `CLASSIC_FEATURES` bit: recursive refraction with Fresnel and total internal reflection.
pub const FEATURE_REFRACTION: u32 = 16;
/// `CLASSIC_FEATURES` bit: reflections perturbed over a lobe of radius `gloss`.
pub const FEATURE_GLOSSY: u32 = 32;
/// `CLASSIC_FEATURES` bit: interpolated vertex normals (off: flat facets).
pub const FEATURE_SMOOTH_NORMALS: u32 = 64;
/// `CLASSIC_FEATURES` bit: reflected and refracted rays that leave the scene see the
/// environment (off: black).
pub const FEATURE_ENVIRONMENT_REFLECTIONS: u32 = 128;
/// Feature bit of motion blur, for every integrator: off compiles the kernel without
/// `MOTION_BLUR` (`bvh/motion.wgsl`), so moving objects stand still at shutter open.
pub const FEATURE_MOTION_BLUR: u32 = 256;
/// `CLASSIC_FEATURES` bit: refractions perturbed over a lobe of radius the dielectric's
/// roughness (`frost`).
pub const FEATURE_FROSTED: u32 = 512;

/// How a feature's value is chosen.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FeatureKind {
    /// `on` or `off`, the `CLASSIC_FEATURES` bit given.
    Toggle(u32),
    /// One of the named values, stored as its index; `on` and `off` name two of them.
    Choice {
        /// The accepted names, by override value.
        values: &'static [&'static str],
        /// The value `on` selects (also the default).
        on: u16,
        /// The value `off` selects.
        off: u16,
    },
    /// A sample count from 1 to [`MAX_SAMPLES`].
    Count,
}

/// Most samples a count feature accepts (per light or glossy reflection and pass).
pub const MAX_SAMPLES: u16 = 256;

/// One feature: its name, kind, default and what it costs (docs/FEATURES.md lists them).
#[derive(Clone, Copy, Debug)]
pub struct FeatureInfo {
    /// The command-line name.
    pub name: &'static str,
    /// Its values.
    pub kind: FeatureKind,
    /// What it does.
    pub what: &'static str,
    /// The default, in words.
    pub default: &'static str,
    /// What it costs, in words.
    pub cost: &'static str,
}

/// Index of `shading` in [`FEATURES`].
const SHADING: usize = 8;
/// Index of `fresnel`.
const FRESNEL: usize = 9;
/// Index of `texture-filter`.
const TEXTURE_FILTER: usize = 10;
/// Index of `light-samples`.
const LIGHT_SAMPLES: usize = 11;
/// Index of `gloss-samples`.
const GLOSS_SAMPLES: usize = 12;
/// Index of `frost-samples`.
const FROST_SAMPLES: usize = 15;

/// Every feature, in `--feature` order.
pub const FEATURES: [FeatureInfo; 16] = [
    FeatureInfo {
        name: "shadows",
        kind: FeatureKind::Toggle(FEATURE_SHADOWS),
        what: "shadow rays towards every light sample",
        default: "on",
        cost: "one shadow ray per light sample",
    },
    FeatureInfo {
        name: "soft-shadows",
        kind: FeatureKind::Toggle(FEATURE_SOFT_SHADOWS),
        what: "area, sphere, disk and spread lights sampled at `light-samples` random points per pass (off: one fixed point, hard shadows)",
        default: "on where the scene has such a light",
        cost: "`light-samples` light samples per extended light",
    },
    FeatureInfo {
        name: "light-transparency",
        kind: FeatureKind::Toggle(FEATURE_LIGHT_TRANSPARENCY),
        what: "shadow rays pass transparent surfaces, tinted by each one's transmittance colour (off: blocked)",
        default: "on where a material is transparent",
        cost: "one closest-hit query per surface crossed (at most 8)",
    },
    FeatureInfo {
        name: "reflection",
        kind: FeatureKind::Toggle(FEATURE_REFLECTION),
        what: "recursive mirror reflection weighted by specular colour + reflectance",
        default: "on where a material reflects",
        cost: "one ray per reflecting hit",
    },
    FeatureInfo {
        name: "refraction",
        kind: FeatureKind::Toggle(FEATURE_REFRACTION),
        what: "recursive refraction (Snell), Fresnel split, total internal reflection",
        default: "on where a material is transparent",
        cost: "one more ray per transparent hit",
    },
    FeatureInfo {
        name: "glossy",
        kind: FeatureKind::Toggle(FEATURE_GLOSSY),
        what: "reflections perturbed over a disk of radius `gloss` around the mirror direction",
        default: "on where a reflecting material has gloss",
        cost: "`gloss-samples` rays instead of one per glossy reflection",
    },
    FeatureInfo {
        name: "smooth-normals",
        kind: FeatureKind::Toggle(FEATURE_SMOOTH_NORMALS),
        what: "barycentric interpolation of vertex normals (off: flat facets)",
        default: "on",
        cost: "none measurable",
    },
    FeatureInfo {
        name: "environment-reflections",
        kind: FeatureKind::Toggle(FEATURE_ENVIRONMENT_REFLECTIONS),
        what: "reflected and refracted rays that leave the scene see the environment (off: black; camera rays always see it)",
        default: "on",
        cost: "one environment lookup per escaping ray",
    },
    FeatureInfo {
        name: "shading",
        kind: FeatureKind::Choice { values: &["lambert", "phong", "blinn-phong"], on: 2, off: 0 },
        what: "highlight model: none, Phong (R.V)^shininess or Blinn-Phong (N.H)^shininess, times the specular colour",
        default: "blinn-phong (the CSE167 model)",
        cost: "a few instructions per light sample",
    },
    FeatureInfo {
        name: "fresnel",
        kind: FeatureKind::Choice { values: &["off", "schlick", "exact"], on: 2, off: 0 },
        what: "share of a transparent surface's light reflected: none (total internal reflection only), Schlick's approximation, or the exact dielectric equations",
        default: "exact",
        cost: "a few instructions per transparent hit",
    },
    FeatureInfo {
        name: "texture-filter",
        kind: FeatureKind::Choice { values: &["material", "nearest", "bilinear", "trilinear"], on: 0, off: 1 },
        what: "texture lookups: each texture's own sampler, or nearest, bilinear, trilinear (mip-mapped) for all (also in the path tracer)",
        default: "material",
        cost: "trilinear reads 8 texels, bilinear 4, nearest 1",
    },
    FeatureInfo {
        name: "light-samples",
        kind: FeatureKind::Count,
        what: "samples per extended light and pass with soft shadows on; chosen, it overrides every light's own count",
        default: "each light's `arealightsamples`, else the scene's `lightsamples` (1)",
        cost: "linear in the count",
    },
    FeatureInfo {
        name: "gloss-samples",
        kind: FeatureKind::Count,
        what: "reflected directions per glossy reflection and pass (as many as the 16-ray stack holds)",
        default: "the scene language's `glosssamples` (1)",
        cost: "linear in the count",
    },
    FeatureInfo {
        name: "motion-blur",
        kind: FeatureKind::Toggle(FEATURE_MOTION_BLUR),
        what: "objects given a motion move over the shutter and each path sees them at its own time, in every integrator (off: they stand still at shutter open)",
        default: "on where something moves",
        cost: "one ray transform per moving primitive tested, boxes swept over the shutter (the motion scene: 1.45x the still frame's time)",
    },
    FeatureInfo {
        name: "frosted",
        kind: FeatureKind::Toggle(FEATURE_FROSTED),
        what: "refractions perturbed over a disk of radius `frost` around the refracted direction (off: sharp refraction)",
        default: "on where a transparent material has frost",
        cost: "`frost-samples` rays instead of one per frosted refraction",
    },
    FeatureInfo {
        name: "frost-samples",
        kind: FeatureKind::Count,
        what: "refracted directions per frosted refraction and pass (as many as the 16-ray stack holds)",
        default: "the scene language's `frostsamples` (1)",
        cost: "linear in the count",
    },
];

/// The switches a render asks for: each feature's chosen value, or the scene's default.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ClassicFeatures {
    chosen: [Option<u16>; FEATURES.len()],
}

/// The override constants and counts a classic kernel is compiled and run with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FeatureConstants {
    /// `CLASSIC_FEATURES`: the `FEATURE_*` bits on.
    pub mask: u32,
    /// `CLASSIC_SHADING`: 0 Lambert, 1 Phong, 2 Blinn-Phong.
    pub shading: u32,
    /// `FRESNEL_MODE`: 0 none, 1 Schlick, 2 exact.
    pub fresnel: u32,
    /// `TEXTURE_FILTER`: 0 the material's, 1 nearest, 2 bilinear, 3 trilinear.
    pub texture_filter: u32,
}

impl Default for FeatureConstants {
    /// Every toggle on, Blinn-Phong, exact Fresnel, the materials' filters.
    fn default() -> Self {
        FeatureConstants { mask: 0xff, shading: 2, fresnel: 2, texture_filter: 0 }
    }
}

impl FeatureConstants {
    /// The pipeline override constants, by WGSL name.
    pub fn overrides(&self) -> [(&'static str, f64); 4] {
        [
            ("CLASSIC_FEATURES", f64::from(self.mask)),
            ("CLASSIC_SHADING", f64::from(self.shading)),
            ("FRESNEL_MODE", f64::from(self.fresnel)),
            ("TEXTURE_FILTER", f64::from(self.texture_filter)),
        ]
    }
}

impl ClassicFeatures {
    /// Sets one feature from `NAME=VALUE` (`on`/`off`, a value name, or a count); errors name
    /// the valid features or values.
    pub fn set(&mut self, text: &str) -> Result<(), String> {
        let (index, value) = parse_feature(text)?;
        self.choose(index, value);
        Ok(())
    }

    /// Sets feature `index` of [`FEATURES`] to `value` as [`parse_feature`] returns them.
    pub fn choose(&mut self, index: usize, value: u16) {
        self.chosen[index] = Some(value);
    }

    /// The constants for a scene that uses the `FEATURE_*` bits `scene_bits`: the chosen
    /// toggles, and the scene's use for the rest.
    pub fn constants(&self, scene_bits: u32) -> FeatureConstants {
        let mut mask = 0;
        for (info, chosen) in FEATURES.iter().zip(self.chosen) {
            if let FeatureKind::Toggle(bit) = info.kind {
                let on = chosen.map_or(scene_bits & bit != 0, |v| v == 1);
                mask |= if on { bit } else { 0 };
            }
        }
        let choice = |index: usize| {
            u32::from(self.chosen[index].unwrap_or(match FEATURES[index].kind {
                FeatureKind::Choice { on, .. } => on,
                _ => 0,
            }))
        };
        FeatureConstants { mask, shading: choice(SHADING), fresnel: choice(FRESNEL), texture_filter: choice(TEXTURE_FILTER) }
    }

    /// Samples per extended light: the chosen count, else `scene_count` (at least 1).
    pub fn light_samples(&self, scene_count: u32) -> u32 {
        self.chosen[LIGHT_SAMPLES].map_or(scene_count, u32::from).max(1)
    }

    /// Whether `light-samples` was chosen, overriding the lights' own counts too.
    pub fn light_samples_forced(&self) -> bool {
        self.chosen[LIGHT_SAMPLES].is_some()
    }

    /// Directions per frosted refraction: the chosen count, else `scene_count` (at least 1).
    pub fn frost_samples(&self, scene_count: u32) -> u32 {
        self.chosen[FROST_SAMPLES].map_or(scene_count, u32::from).max(1)
    }

    /// Directions per glossy reflection: the chosen count, else `scene_count` (at least 1).
    pub fn gloss_samples(&self, scene_count: u32) -> u32 {
        self.chosen[GLOSS_SAMPLES].map_or(scene_count, u32::from).max(1)
    }

    /// The features chosen, as `NAME=VALUE` (for reports and reproducing command lines).
    pub fn chosen(&self) -> Vec<String> {
        FEATURES.iter().zip(self.chosen).filter_map(|(info, v)| v.map(|v| format!("{}={}", info.name, value_name(info, v)))).collect()
    }
}

/// The name of value `v` of `info`.
fn value_name(info: &FeatureInfo, v: u16) -> String {
    match info.kind {
        FeatureKind::Toggle(_) => if v == 1 { "on" } else { "off" }.to_string(),
        FeatureKind::Choice { values, .. } => values[usize::from(v)].to_string(),
        FeatureKind::Count => v.to_string(),
    }
}

/// The valid values of `info`, for error messages.
fn valid_values(info: &FeatureInfo) -> String {
    match info.kind {
        FeatureKind::Toggle(_) => "on or off".to_string(),
        FeatureKind::Choice { values, .. } => {
            let aliases = if values.contains(&"off") { "on" } else { "on, off" };
            format!("{aliases}, {}", values.join(", "))
        }
        FeatureKind::Count => format!("a whole number from 1 to {MAX_SAMPLES}"),
    }
}

/// Parses `NAME=VALUE` into the feature's index in [`FEATURES`] and its value.
pub fn parse_feature(text: &str) -> Result<(usize, u16), String> {
    let names = || FEATURES.iter().map(|f| f.name).collect::<Vec<_>>().join(", ");
    let Some((name, value)) = text.split_once('=') else {
        return Err(format!("--feature {text}: expected NAME=VALUE, e.g. shadows=off; features: {}", names()));
    };
    let (name, value) = (name.trim(), value.trim());
    let Some(index) = FEATURES.iter().position(|f| f.name == name) else {
        return Err(format!("--feature {text}: unknown feature '{name}'; features: {}", names()));
    };
    let info = &FEATURES[index];
    let parsed = match (info.kind, value) {
        (FeatureKind::Toggle(_), "on") => Some(1),
        (FeatureKind::Toggle(_), "off") => Some(0),
        (FeatureKind::Choice { on, .. }, "on") => Some(on),
        (FeatureKind::Choice { off, .. }, "off") => Some(off),
        (FeatureKind::Choice { values, .. }, v) => values.iter().position(|n| *n == v).map(|i| i as u16),
        (FeatureKind::Count, v) => v.parse::<u16>().ok().filter(|n| (1..=MAX_SAMPLES).contains(n)),
        _ => None,
    };
    parsed.map(|v| (index, v)).ok_or_else(|| format!("--feature {text}: '{value}' is not a value of {name}; use {}", valid_values(info)))
}

/// The feature table as Markdown rows (`| name | values | default | what | cost |`), the
/// source of docs/FEATURES.md's table.
pub fn markdown_table() -> String {
    let mut out = String::from("| Feature | Values | Default | What it does | Cost |\n| --- | --- | --- | --- | --- |\n");
    for info in &FEATURES {
        out += &format!("| `{}` | {} | {} | {} | {} |\n", info.name, valid_values(info), info.default, info.what, info.cost);
    }
    out
}
