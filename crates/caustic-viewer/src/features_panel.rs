//! The panel's "Features" section: one control per entry of the feature table
//! ([`caustic_kernels::features::FEATURES`], the table `caustic render --feature` reads), so the
//! window offers exactly the switches the command line does: a checkbox per toggle, a box per
//! choice, a number per sample count. [`FeaturePanel`] is the state behind the controls (no UI),
//! which turns into the [`ClassicFeatures`] a render is compiled with and into `--feature`
//! arguments.

use caustic_kernels::features::{ClassicFeatures, FEATURES, FeatureInfo, FeatureKind, MAX_SAMPLES, parse_feature};
use egui::{ComboBox, DragValue, Ui};

/// One feature's control.
#[derive(Clone, Debug, PartialEq)]
pub struct FeatureControl {
    /// Index in [`FEATURES`].
    pub index: usize,
    /// The value chosen in the panel (as [`parse_feature`] numbers values); `None` leaves the
    /// scene's default.
    pub chosen: Option<u16>,
    /// The value the scene gets when nothing is chosen, for toggles and choices (sample counts
    /// come from the scene's options; their default is described in words by the table).
    pub scene_default: Option<u16>,
}

impl FeatureControl {
    /// The table entry.
    pub fn info(&self) -> &'static FeatureInfo {
        &FEATURES[self.index]
    }

    /// The value in effect: the chosen one, else the scene's default.
    pub fn value(&self) -> Option<u16> {
        self.chosen.or(self.scene_default)
    }

    /// The hover text: what the feature does, its default and its cost.
    pub fn hover_text(&self) -> String {
        format!("{}\ndefault: {}\ncost: {}", self.info().what, self.info().default, self.info().cost)
    }
}

/// The state of the Features section.
#[derive(Clone, Debug, PartialEq)]
pub struct FeaturePanel {
    /// One control per feature, in table order.
    pub controls: Vec<FeatureControl>,
}

impl FeaturePanel {
    /// The controls for every feature of the table: those `features` sets chosen, the others
    /// at the default of a scene that uses the `FEATURE_*` bits `scene_bits`.
    pub fn new(features: &ClassicFeatures, scene_bits: u32) -> FeaturePanel {
        let mut chosen = [None; FEATURES.len()];
        for text in features.chosen() {
            if let Ok((index, value)) = parse_feature(&text) {
                chosen[index] = Some(value);
            }
        }
        let controls = FEATURES
            .iter()
            .enumerate()
            .map(|(index, info)| FeatureControl { index, chosen: chosen[index], scene_default: scene_default(info, scene_bits) })
            .collect();
        FeaturePanel { controls }
    }

    /// The switches the controls choose, for [`caustic_gpu::RenderSettings::features`].
    pub fn features(&self) -> ClassicFeatures {
        let mut features = ClassicFeatures::default();
        for control in &self.controls {
            if let Some(value) = control.chosen {
                features.choose(control.index, value);
            }
        }
        features
    }

    /// The `--feature NAME=VALUE` arguments of `caustic render` that choose the same.
    pub fn arguments(&self) -> Vec<String> {
        self.features().chosen().into_iter().flat_map(|f| ["--feature".to_string(), f]).collect()
    }

    /// Draws the controls; returns whether any choice changed.
    pub fn show(&mut self, ui: &mut Ui) -> bool {
        let before = self.clone();
        for control in &mut self.controls {
            ui.horizontal(|ui| feature_row(ui, control));
        }
        *self != before
    }
}

/// The scene's value of a toggle (its bit in `scene_bits`) or a choice (the one `on` names).
fn scene_default(info: &FeatureInfo, scene_bits: u32) -> Option<u16> {
    match info.kind {
        FeatureKind::Toggle(bit) => Some(u16::from(scene_bits & bit != 0)),
        FeatureKind::Choice { on, .. } => Some(on),
        FeatureKind::Count => None,
    }
}

/// One row: the control, and a button back to the scene's default when a value is chosen.
fn feature_row(ui: &mut Ui, control: &mut FeatureControl) {
    let hover = control.hover_text();
    let info = control.info();
    match info.kind {
        FeatureKind::Toggle(_) => {
            let mut on = control.value() == Some(1);
            if ui.checkbox(&mut on, control.info().name).on_hover_text(&hover).changed() {
                control.chosen = Some(u16::from(on));
            }
        }
        FeatureKind::Choice { values, .. } => {
            let current = control.value().map_or("?", |v| values[usize::from(v)]);
            ComboBox::from_label(control.info().name).selected_text(current).show_ui(ui, |ui| {
                for (i, name) in values.iter().enumerate() {
                    if ui.selectable_label(control.value() == Some(i as u16), *name).clicked() {
                        control.chosen = Some(i as u16);
                    }
                }
            });
            ui.label("").on_hover_text(&hover);
        }
        FeatureKind::Count => match &mut control.chosen {
            Some(count) => {
                ui.add(DragValue::new(count).range(1..=MAX_SAMPLES).prefix(format!("{} ", info.name))).on_hover_text(&hover);
            }
            None => {
                ui.label(format!("{}: scene's", control.info().name)).on_hover_text(&hover);
                if ui.small_button("set").on_hover_text("choose a count for this view").clicked() {
                    control.chosen = Some(1);
                }
            }
        },
    }
    if control.chosen.is_some() && ui.small_button("scene default").on_hover_text(format!("back to: {}", control.info().default)).clicked() {
        control.chosen = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_panel_covers_the_table_and_round_trips_to_the_same_feature_arguments() {
        let panel = FeaturePanel::new(&ClassicFeatures::default(), 0);
        let names: Vec<&str> = panel.controls.iter().map(|c| c.info().name).collect();
        let table: Vec<&str> = FEATURES.iter().map(|f| f.name).collect();
        assert_eq!(names, table, "one control per feature, in table order");
        assert!(panel.arguments().is_empty(), "nothing chosen: no --feature");

        // Choose in every control a value other than the scene's default.
        let mut edited = panel.clone();
        for control in &mut edited.controls {
            control.chosen = Some(match control.info().kind {
                FeatureKind::Toggle(_) => 1 - control.scene_default.unwrap_or(0),
                FeatureKind::Choice { values, on, .. } => ((usize::from(on) + 1) % values.len()) as u16,
                FeatureKind::Count => 7,
            });
        }
        let arguments = edited.arguments();
        println!("{}", arguments.join(" "));
        assert_eq!(arguments.len(), 2 * FEATURES.len(), "every feature on the command line");

        // The arguments parsed as `caustic render` parses them give back the same controls.
        let mut parsed = ClassicFeatures::default();
        for pair in arguments.chunks(2) {
            assert_eq!(pair[0], "--feature");
            parsed.set(&pair[1]).expect("the command line accepts what the panel writes");
        }
        assert_eq!(parsed, edited.features());
        assert_eq!(FeaturePanel::new(&parsed, 0), edited, "the panel built from the parsed switches is the edited one");
        assert_eq!(FeaturePanel::new(&parsed, 0).arguments(), arguments);
    }

    #[test]
    fn the_scene_defaults_follow_the_scene_bits() {
        let shadows = caustic_kernels::features::FEATURE_SHADOWS;
        let with = FeaturePanel::new(&ClassicFeatures::default(), shadows);
        let without = FeaturePanel::new(&ClassicFeatures::default(), 0);
        let shadow_control = |p: &FeaturePanel| p.controls.iter().find(|c| c.info().name == "shadows").unwrap().value();
        assert_eq!((shadow_control(&with), shadow_control(&without)), (Some(1), Some(0)));
        let shading = with.controls.iter().find(|c| c.info().name == "shading").unwrap();
        assert_eq!(shading.value(), Some(2), "blinn-phong unless chosen");
        assert!(shading.hover_text().contains(shading.info().cost));
    }
}
