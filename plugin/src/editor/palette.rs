//! # The editor's colours of the room and the sheet, shared by the 3D view ([`super::sheet_view`])
//! and its top-view inset ([`super::room_map`]).

use egui::Color32;

/// Background of the view.
pub const BACKGROUND: Color32 = Color32::from_rgb(30, 34, 42);
/// Table top colour (a wood tone, far from the paper's hues).
pub const TABLE_COLOUR: Color32 = Color32::from_rgb(125, 80, 50);
/// Wall colour.
pub const WALL_COLOUR: Color32 = Color32::from_rgba_premultiplied(64, 78, 96, 200);
/// Floor grid colour.
pub const FLOOR_COLOUR: Color32 = Color32::from_rgb(58, 64, 76);
/// Listener marker colour.
pub const LISTENER_COLOUR: Color32 = Color32::from_rgb(110, 180, 255);
/// Sheet outline colour.
pub const OUTLINE_COLOUR: Color32 = Color32::from_rgba_premultiplied(40, 38, 34, 160);
