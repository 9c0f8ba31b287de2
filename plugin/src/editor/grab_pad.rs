//! # The grab pad: hands on the sheet
//!
//! A diagram of the sheet seen from above (back edge at the top, the listener's side at the
//! bottom) with a zone for each grab slot: the back, front, left and right edges, and the
//! corners (any corner zone grabs all four). Pressing a zone grabs, releasing lets go — exactly
//! a held MIDI note ([`crate::gesture_map`]: 48 back, 50 front, 52 left, 53 right, 55 corners)
//! with the pad's grip as velocity. With **Hold** on, a click latches the grab instead (one
//! mouse cannot hold an edge and drag the XY pad at the same time). **Reset sheet** sends note
//! 36, **Let go** note 59 (on click).
//!
//! The pad does not talk to the engine itself: it hands [`MidiInput`] messages to a sink, which
//! the editor pushes into the lock-free GUI → audio queue
//! ([`crate::engine::ViewShared::gui_midi`]); the audio thread feeds them to the engine like
//! MIDI notes.
//!
//! ```text
//!   ┌──┬──────────┬──┐
//!   │c │   back   │ c│      c = corners (all four)
//!   ├──┼──────────┼──┤
//!   │  │          │  │
//!   │l │  sheet   │ r│
//!   │  │          │  │
//!   ├──┼──────────┼──┤
//!   │c │  front   │ c│
//!   └──┴──────────┴──┘
//! ```

use egui::{Align2, Color32, FontId, Rect, Sense, Stroke, StrokeKind, Ui, Vec2, pos2};
use sim_core::GrabSlot;

use crate::gesture_map::{MidiInput, NOTE_RELEASE_ALL, NOTE_RESET, note_for_slot};

/// Thickness of the edge and corner zones, as a fraction of the pad's smaller side.
pub const BAND_FRAC: f32 = 0.24;
/// Default grip (note velocity) of the pad.
pub const DEFAULT_GRIP: f32 = 0.7;

/// What a zone of the pad grabs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum GrabTarget {
    /// The back edge (+y, away from the listener).
    Back,
    /// The front edge.
    Front,
    /// The left edge.
    Left,
    /// The right edge.
    Right,
    /// All four corners.
    Corners,
}

impl GrabTarget {
    /// Every target.
    pub const ALL: [GrabTarget; 5] = [
        GrabTarget::Back,
        GrabTarget::Front,
        GrabTarget::Left,
        GrabTarget::Right,
        GrabTarget::Corners,
    ];

    /// The simulation's grab slot.
    pub const fn slot(self) -> GrabSlot {
        match self {
            GrabTarget::Back => GrabSlot::Back,
            GrabTarget::Front => GrabSlot::Front,
            GrabTarget::Left => GrabSlot::Left,
            GrabTarget::Right => GrabSlot::Right,
            GrabTarget::Corners => GrabSlot::Corners,
        }
    }

    /// The MIDI note that grabs it.
    pub const fn note(self) -> u8 {
        note_for_slot(self.slot())
    }

    /// Short label.
    pub const fn label(self) -> &'static str {
        match self {
            GrabTarget::Back => "back",
            GrabTarget::Front => "front",
            GrabTarget::Left => "left",
            GrabTarget::Right => "right",
            GrabTarget::Corners => "corners",
        }
    }

    const fn index(self) -> usize {
        self as usize
    }
}

/// The zones of a pad occupying `rect` (the corner target has four).
pub fn zones(rect: Rect) -> [(GrabTarget, Rect); 8] {
    let b = BAND_FRAC * rect.width().min(rect.height());
    let (l, r, t, bo) = (rect.left(), rect.right(), rect.top(), rect.bottom());
    let z = |x0: f32, y0: f32, x1: f32, y1: f32| Rect::from_min_max(pos2(x0, y0), pos2(x1, y1));
    [
        (GrabTarget::Back, z(l + b, t, r - b, t + b)),
        (GrabTarget::Front, z(l + b, bo - b, r - b, bo)),
        (GrabTarget::Left, z(l, t + b, l + b, bo - b)),
        (GrabTarget::Right, z(r - b, t + b, r, bo - b)),
        (GrabTarget::Corners, z(l, t, l + b, t + b)),
        (GrabTarget::Corners, z(r - b, t, r, t + b)),
        (GrabTarget::Corners, z(l, bo - b, l + b, bo)),
        (GrabTarget::Corners, z(r - b, bo - b, r, bo)),
    ]
}

/// The sheet drawn in the middle of the pad (not a target).
pub fn sheet_rect(rect: Rect) -> Rect {
    rect.shrink(BAND_FRAC * rect.width().min(rect.height()))
}

/// The target under `pos`, if any.
pub fn hit(rect: Rect, pos: egui::Pos2) -> Option<GrabTarget> {
    zones(rect)
        .into_iter()
        .find(|(_, z)| z.contains(pos))
        .map(|(t, _)| t)
}

/// Press/release logic of the pad, independent of drawing.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GrabState {
    pressed: Option<GrabTarget>,
    latched: [bool; 5],
}

impl GrabState {
    /// The primary button went down on the pad over `under` (`None`: between the zones).
    pub fn press(
        &mut self,
        under: Option<GrabTarget>,
        latch: bool,
        grip: f32,
        out: &mut impl FnMut(MidiInput),
    ) {
        let velocity = if grip.is_finite() {
            grip.clamp(0.01, 1.0)
        } else {
            DEFAULT_GRIP
        };
        let Some(t) = under else {
            return;
        };
        if latch {
            let held = &mut self.latched[t.index()];
            *held = !*held;
            out(if *held {
                MidiInput::NoteOn {
                    key: t.note(),
                    velocity,
                }
            } else {
                MidiInput::NoteOff { key: t.note() }
            });
        } else if !self.latched[t.index()] && self.pressed.is_none() {
            self.pressed = Some(t);
            out(MidiInput::NoteOn {
                key: t.note(),
                velocity,
            });
        }
    }

    /// The primary button went up (anywhere): a held, unlatched grab lets go.
    pub fn release(&mut self, out: &mut impl FnMut(MidiInput)) {
        if let Some(t) = self.pressed.take() {
            out(MidiInput::NoteOff { key: t.note() });
        }
    }

    /// Lets go of every latched grab (when Hold is switched off).
    pub fn unlatch(&mut self, out: &mut impl FnMut(MidiInput)) {
        for t in GrabTarget::ALL {
            if std::mem::take(&mut self.latched[t.index()]) {
                out(MidiInput::NoteOff { key: t.note() });
            }
        }
    }

    /// Forgets every grab (after a "let go of everything" message was sent).
    pub fn forget_all(&mut self) {
        self.latched = [false; 5];
        self.pressed = None;
    }

    /// Is the target held (pressed now or latched)?
    pub fn is_held(&self, t: GrabTarget) -> bool {
        self.pressed == Some(t) || self.latched[t.index()]
    }
}

/// Rectangles of the pad's buttons, for the layout probe.
#[derive(Clone, Copy, Debug)]
pub struct ButtonRects {
    /// The Reset button.
    pub reset: Rect,
    /// The Let go button.
    pub let_go: Rect,
    /// The Hold checkbox.
    pub hold: Rect,
}

/// The grab pad widget with its buttons.
#[derive(Debug)]
pub struct GrabPad {
    state: GrabState,
    /// Latch grabs on click instead of holding them while pressed.
    pub latch: bool,
    /// Grip (note velocity) 0–1.
    pub grip: f32,
}

impl Default for GrabPad {
    fn default() -> Self {
        Self {
            state: GrabState::default(),
            latch: false,
            grip: DEFAULT_GRIP,
        }
    }
}

impl GrabPad {
    /// Draws the diagram (`size` logical pixels) and handles the pointer on it; sends messages
    /// to `sink`. Returns the diagram's rectangle.
    ///
    /// Presses and releases are taken from the frame's input events, in order, so a click
    /// shorter than a frame still grabs and lets go.
    pub fn pad(&mut self, ui: &mut Ui, size: Vec2, sink: &mut impl FnMut(MidiInput)) -> Rect {
        let (rect, response) = ui.allocate_exact_size(size, Sense::click_and_drag());
        let on_top = response.contains_pointer() || response.is_pointer_button_down_on();
        let events: Vec<(egui::Pos2, bool)> = ui.input(|i| {
            i.events
                .iter()
                .filter_map(|e| match e {
                    egui::Event::PointerButton {
                        pos,
                        button: egui::PointerButton::Primary,
                        pressed,
                        ..
                    } => Some((*pos, *pressed)),
                    _ => None,
                })
                .collect()
        });
        for (pos, pressed) in events {
            if !pressed {
                self.state.release(sink);
            } else if on_top && rect.contains(pos) {
                self.state
                    .press(hit(rect, pos), self.latch, self.grip, sink);
            }
        }
        let hover = response.hover_pos().and_then(|p| hit(rect, p));
        self.paint(ui, rect, hover);
        rect
    }

    /// Draws the Hold switch, the grip, and the Reset and Let go buttons.
    pub fn buttons(&mut self, ui: &mut Ui, sink: &mut impl FnMut(MidiInput)) -> ButtonRects {
        let mut rects = ButtonRects {
            reset: Rect::NOTHING,
            let_go: Rect::NOTHING,
            hold: Rect::NOTHING,
        };
        ui.horizontal(|ui| {
            let was = self.latch;
            rects.hold = ui
                .checkbox(&mut self.latch, "Hold")
                .on_hover_text("Click a zone to grab, click it again to let go")
                .rect;
            if was && !self.latch {
                self.state.unlatch(sink);
            }
            ui.add(
                egui::Slider::new(&mut self.grip, 0.05..=1.0)
                    .text("grip")
                    .fixed_decimals(2),
            )
            .on_hover_text("How fast the hands reach their target (note velocity)");
        });
        ui.horizontal(|ui| {
            let r = ui
                .button("Reset sheet")
                .on_hover_text("A new flat sheet (note 36)");
            rects.reset = r.rect;
            if r.clicked() {
                sink(MidiInput::NoteOn {
                    key: NOTE_RESET,
                    velocity: 1.0,
                });
                sink(MidiInput::NoteOff { key: NOTE_RESET });
            }
            let r = ui
                .button("Let go")
                .on_hover_text("Release every hand (note 59)");
            rects.let_go = r.rect;
            if r.clicked() {
                sink(MidiInput::NoteOn {
                    key: NOTE_RELEASE_ALL,
                    velocity: 1.0,
                });
                sink(MidiInput::NoteOff {
                    key: NOTE_RELEASE_ALL,
                });
                self.state.forget_all();
            }
        });
        rects
    }

    fn paint(&self, ui: &Ui, rect: Rect, hover: Option<GrabTarget>) {
        let painter = ui.painter_at(rect.expand(1.0));
        let visuals = ui.visuals();
        painter.rect_filled(rect, 4.0, visuals.extreme_bg_color);
        let sheet = sheet_rect(rect);
        painter.rect_filled(sheet, 1.0, Color32::from_rgb(236, 232, 220));
        painter.text(
            sheet.center(),
            Align2::CENTER_CENTER,
            "sheet\n(top view)",
            FontId::proportional(11.0),
            Color32::from_gray(90),
        );
        for (t, z) in zones(rect) {
            let held = self.state.is_held(t);
            let fill = if held {
                Color32::from_rgb(60, 170, 105)
            } else if hover == Some(t) {
                visuals.widgets.hovered.bg_fill
            } else {
                visuals.widgets.inactive.bg_fill
            };
            painter.rect_filled(z.shrink(1.5), 3.0, fill);
            painter.rect_stroke(
                z.shrink(1.5),
                3.0,
                Stroke::new(1.0, visuals.widgets.inactive.bg_stroke.color),
                StrokeKind::Inside,
            );
            if t != GrabTarget::Corners {
                painter.text(
                    z.center(),
                    Align2::CENTER_CENTER,
                    t.label(),
                    FontId::proportional(11.0),
                    if held {
                        Color32::WHITE
                    } else {
                        visuals.text_color()
                    },
                );
            } else {
                painter.circle_filled(z.center(), 3.0, visuals.text_color());
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use egui::vec2;

    fn rect() -> Rect {
        Rect::from_min_size(pos2(100.0, 50.0), vec2(150.0, 200.0))
    }

    #[test]
    fn hit_testing_finds_each_zone() {
        let r = rect(); // band = 0.24 · 150 = 36
        assert_eq!(hit(r, pos2(175.0, 60.0)), Some(GrabTarget::Back));
        assert_eq!(hit(r, pos2(175.0, 240.0)), Some(GrabTarget::Front));
        assert_eq!(hit(r, pos2(110.0, 150.0)), Some(GrabTarget::Left));
        assert_eq!(hit(r, pos2(240.0, 150.0)), Some(GrabTarget::Right));
        for p in [(105.0, 55.0), (245.0, 55.0), (105.0, 245.0), (245.0, 245.0)] {
            assert_eq!(hit(r, pos2(p.0, p.1)), Some(GrabTarget::Corners), "{p:?}");
        }
        assert_eq!(hit(r, r.center()), None, "the sheet itself is not a target");
        assert_eq!(hit(r, pos2(10.0, 10.0)), None);
        assert!(!sheet_rect(r).intersects(zones(r)[0].1.shrink(0.5)));
    }

    #[test]
    fn zones_tile_the_border_without_overlap() {
        let r = rect();
        let z = zones(r);
        for (i, (_, a)) in z.iter().enumerate() {
            assert!(r.contains_rect(*a));
            for (_, b) in &z[i + 1..] {
                assert!(!a.shrink(0.01).intersects(b.shrink(0.01)), "{a:?} {b:?}");
            }
        }
        let area: f32 = z.iter().map(|(_, a)| a.area()).sum::<f32>() + sheet_rect(r).area();
        assert!((area - r.area()).abs() < 1e-2);
    }

    /// Feeds steps (`Some(under)` = press over a target, `None` = release).
    fn run(
        state: &mut GrabState,
        steps: &[Option<Option<GrabTarget>>],
        latch: bool,
    ) -> Vec<MidiInput> {
        let mut out = Vec::new();
        for step in steps {
            match step {
                Some(under) => state.press(*under, latch, 0.5, &mut |m| out.push(m)),
                None => state.release(&mut |m| out.push(m)),
            }
        }
        out
    }

    #[test]
    fn press_grabs_and_release_lets_go() {
        let mut s = GrabState::default();
        let front = Some(Some(GrabTarget::Front));
        let out = run(&mut s, &[front], false);
        assert_eq!(
            out,
            vec![MidiInput::NoteOn {
                key: 50,
                velocity: 0.5
            }]
        );
        assert!(s.is_held(GrabTarget::Front));
        // A second press while held (another button) does not grab twice.
        assert!(run(&mut s, &[Some(Some(GrabTarget::Back))], false).is_empty());
        // Released anywhere: the slot that was grabbed lets go.
        let out = run(&mut s, &[None], false);
        assert_eq!(out, vec![MidiInput::NoteOff { key: 50 }]);
        assert!(!s.is_held(GrabTarget::Front));
        // A press between the zones does nothing, nor does its release.
        assert!(run(&mut s, &[Some(None), None], false).is_empty());
        // A click shorter than a frame is a grab and a release, in order.
        let out = run(&mut s, &[Some(Some(GrabTarget::Right)), None], false);
        assert_eq!(
            out,
            vec![
                MidiInput::NoteOn {
                    key: 53,
                    velocity: 0.5
                },
                MidiInput::NoteOff { key: 53 }
            ]
        );
    }

    #[test]
    fn hold_mode_latches_until_clicked_again_or_switched_off() {
        let mut s = GrabState::default();
        let c = Some(Some(GrabTarget::Corners));
        let b = Some(Some(GrabTarget::Back));
        let out = run(&mut s, &[c, None, b, None], true);
        assert_eq!(
            out,
            vec![
                MidiInput::NoteOn {
                    key: 55,
                    velocity: 0.5
                },
                MidiInput::NoteOn {
                    key: 48,
                    velocity: 0.5
                }
            ]
        );
        assert!(s.is_held(GrabTarget::Corners) && s.is_held(GrabTarget::Back));
        let out = run(&mut s, &[c, None], true);
        assert_eq!(out, vec![MidiInput::NoteOff { key: 55 }]);
        let mut out = Vec::new();
        s.unlatch(&mut |m| out.push(m));
        assert_eq!(out, vec![MidiInput::NoteOff { key: 48 }]);
        assert!(!s.is_held(GrabTarget::Back));
    }

    #[test]
    fn grip_becomes_a_sane_velocity() {
        let mut s = GrabState::default();
        let mut out = Vec::new();
        s.press(Some(GrabTarget::Left), false, f32::NAN, &mut |m| {
            out.push(m)
        });
        assert_eq!(
            out,
            vec![MidiInput::NoteOn {
                key: 52,
                velocity: DEFAULT_GRIP
            }]
        );
    }

    #[test]
    fn notes_match_the_midi_map() {
        let notes: Vec<u8> = GrabTarget::ALL.iter().map(|t| t.note()).collect();
        assert_eq!(notes, vec![48, 50, 52, 53, 55]);
    }
}
