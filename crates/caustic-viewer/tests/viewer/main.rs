//! The viewer's integration tests as one binary: the display path and the feature panel.

mod display;
mod features;
