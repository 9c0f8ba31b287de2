//! # The editor as the host sees it
//!
//! nice-plug asks the plugin for its editor once, when the plugin is created, and then opens
//! and closes windows from it. [`EditorShell`] wraps nice-plug-egui's editor to add two things
//! that editor does not do in version 0.6:
//!
//! 1. **A saved window size.** The host asks the editor for its size before opening a window.
//!    The shell keeps the egui editor's size in step with the persisted
//!    [`super::window_size::EditorSize`]: when a project was loaded with another size, the next
//!    window opens at that size (the egui editor is rebuilt while no window is open). The size
//!    reported to the host is that logical size times the display scale the window draws at.
//! 2. **Knowing when the window closes.** nice-plug-egui 0.6 never calls
//!    `NiceEguiApp::editor_closed`. The shell's window handle ([`ShellHandle`]), which the host
//!    wrapper drops when it destroys the window, does the closing work: it tells the simulation
//!    to stop copying the mesh for the view (`ViewShared::open`) and drops the host's GUI
//!    context held by the window (it keeps the plugin wrapper alive; holding it past the
//!    window would leak the plugin instance). Hiding and showing the window also switch the
//!    copying off and on.

use std::error::Error;
use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};

use nice_plug::context::gui::GuiContext;
use nice_plug::editor::dpi::{LogicalSize, NativeSize, Size};
use nice_plug::editor::{
    Editor, EditorHandle, HostMethods, Modifiers, ParentWindowHandle, ResizeHint, SpawnedEditor,
    VirtualKeyCode,
};
use nice_plug::plugin::TrackInfo;
use nice_plug_egui::{
    EguiEditor, EguiEditorHandle, EguiEditorState, EguiNiceSettings, RepaintNotifier,
    create_egui_editor,
};

use super::window_size::MIN_SIZE;
use super::{EditorParts, PapierEditor};

/// What the shell and the window share.
#[derive(Default)]
pub struct Session {
    /// The host's GUI context while a window is open (set by the window's `build`).
    pub gui: Mutex<Option<GuiContext>>,
    /// The display's scale (physical pixels per logical pixel) the last window was drawn at,
    /// as `f32` bits; 0 until a window has drawn.
    display_scale: AtomicU32,
}

impl Session {
    /// The GUI context, if a window is open.
    pub fn gui(&self) -> Option<GuiContext> {
        self.gui.lock().ok().and_then(|g| g.clone())
    }

    /// Notes the display's scale a window draws at.
    pub fn set_display_scale(&self, scale: f32) {
        if scale.is_finite() && scale > 0.0 {
            self.display_scale.store(scale.to_bits(), Ordering::Relaxed);
        }
    }

    /// The display's scale the last window was drawn at, if one has drawn.
    pub fn display_scale(&self) -> Option<f32> {
        match self.display_scale.load(Ordering::Relaxed) {
            0 => None,
            bits => Some(f32::from_bits(bits)),
        }
    }

    /// Forgets the GUI context (the window closed).
    pub fn close(&self) {
        let old = self.gui.lock().ok().and_then(|mut g| g.take());
        drop(old);
    }
}

struct Inner {
    egui: EguiEditor<PapierEditor>,
    state: Arc<EguiEditorState>,
}

/// The plugin's editor.
pub struct EditorShell {
    parts: EditorParts,
    session: Arc<Session>,
    inner: Mutex<Inner>,
    standalone: AtomicBool,
}

/// The logical size an egui editor state holds, rounded.
fn logical_size(state: &EguiEditorState) -> (u32, u32) {
    match state.size() {
        Size::Logical(l) => (l.width.round() as u32, l.height.round() as u32),
        Size::Physical(_) => {
            let l = state.logical_size();
            (l.width.round() as u32, l.height.round() as u32)
        }
    }
}

fn build(parts: &EditorParts, session: &Arc<Session>, (w, h): (u32, u32)) -> Inner {
    let state = EguiEditorState::from_size(LogicalSize::new(f64::from(w), f64::from(h)), 1.0);
    let settings = EguiNiceSettings::new()
        .with_tile("Papier")
        .with_resize_hint(
            ResizeHint::RESIZABLE
                .with_min_logical_size(LogicalSize::new(MIN_SIZE.0 as f32, MIN_SIZE.1 as f32)),
        );
    let egui = create_egui_editor(
        state.clone(),
        RepaintNotifier::new(),
        settings,
        PapierEditor::new(parts.clone(), session.clone()),
    )
    .expect("nice-plug-egui always creates an editor");
    Inner { egui, state }
}

impl EditorShell {
    /// The editor for these parts.
    pub fn new(parts: EditorParts) -> Self {
        let session = Arc::new(Session::default());
        let size = parts.params.editor_size.clamped();
        let inner = build(&parts, &session, size);
        Self {
            parts,
            session,
            inner: Mutex::new(inner),
            standalone: AtomicBool::new(false),
        }
    }

    /// The egui editor, rebuilt first if no window is open and the saved size changed.
    fn current(&self) -> MutexGuard<'_, Inner> {
        let mut g = self.inner.lock().unwrap_or_else(|e| e.into_inner());
        let want = self.parts.params.editor_size.clamped();
        if !g.state.is_open() && logical_size(&g.state) != want {
            *g = build(&self.parts, &self.session, want);
            if self.standalone.load(Ordering::Relaxed) {
                // SAFETY: the host told us (below) that this process is the standalone.
                unsafe { g.egui.assume_standalone_in_process() };
            }
        }
        g
    }
}

impl Editor for EditorShell {
    type Handle = ShellHandle;

    fn spawn(
        &self,
        parent: Option<ParentWindowHandle>,
        wait_for_parent: bool,
        fallback_scale_factor: Option<f64>,
        gui_context: GuiContext,
        host: Option<HostMethods>,
    ) -> Result<SpawnedEditor<Self::Handle>, Box<dyn Error>> {
        let spawned = self.current().egui.spawn(
            parent,
            wait_for_parent,
            fallback_scale_factor,
            gui_context,
            host,
        )?;
        self.parts.view.open.store(true, Ordering::Relaxed);
        Ok(SpawnedEditor {
            handle: ShellHandle {
                inner: spawned.handle,
                closer: CloseGuard {
                    parts: self.parts.clone(),
                    session: self.session.clone(),
                },
            },
            window: spawned.window,
        })
    }

    fn size(&self) -> NativeSize<u32> {
        let g = self.current();
        // nice-plug-egui 0.6 learns the display's scale only when the window is resized, so
        // until then it reports logical pixels as physical ones; the scale the window draws at
        // (egui's native pixels per point) is the one that holds.
        match self.session.display_scale() {
            Some(scale) => {
                let (w, h) = logical_size(&g.state);
                NativeSize::from_size(
                    Size::Logical(LogicalSize::new(f64::from(w), f64::from(h))),
                    f64::from(scale),
                )
            }
            None => g.egui.size(),
        }
    }

    fn resize_hint(&self) -> ResizeHint {
        self.current().egui.resize_hint()
    }

    fn track_info_updated(&self, info: TrackInfo) {
        self.current().egui.track_info_updated(info);
    }

    unsafe fn assume_standalone_in_process(&self) {
        self.standalone.store(true, Ordering::Relaxed);
        // SAFETY: same contract as ours.
        unsafe { self.current().egui.assume_standalone_in_process() };
    }
}

/// Does the closing work when the host drops the window handle.
struct CloseGuard {
    parts: EditorParts,
    session: Arc<Session>,
}

impl Drop for CloseGuard {
    fn drop(&mut self) {
        self.parts.view.open.store(false, Ordering::Relaxed);
        self.session.close();
    }
}

/// The handle of an open window.
pub struct ShellHandle {
    inner: EguiEditorHandle,
    closer: CloseGuard,
}

type EguiHandle = EguiEditorHandle;

impl EditorHandle for ShellHandle {
    type Window = <EguiHandle as EditorHandle>::Window;
    type Error = <EguiHandle as EditorHandle>::Error;

    fn run_until_closed(window: Self::Window) -> Result<(), Self::Error> {
        EguiHandle::run_until_closed(window)
    }

    fn set_parent(
        &self,
        parent: ParentWindowHandle,
        window: &Self::Window,
    ) -> Result<(), Self::Error> {
        self.inner.set_parent(parent, window)
    }

    fn show(&self, window: &Self::Window) -> Result<(), Self::Error> {
        self.closer.parts.view.open.store(true, Ordering::Relaxed);
        self.inner.show(window)
    }

    fn hide(&self, window: &Self::Window) -> Result<(), Self::Error> {
        self.closer.parts.view.open.store(false, Ordering::Relaxed);
        self.inner.hide(window)
    }

    fn set_size(
        &self,
        new_size: NativeSize<u32>,
        window: &Self::Window,
    ) -> Result<(), Self::Error> {
        self.inner.set_size(new_size, window)
    }

    fn host_main_thread_callback(&self, window: &Self::Window) {
        self.inner.host_main_thread_callback(window);
    }

    fn adjust_size(
        &self,
        new_size: NativeSize<u32>,
        window: &Self::Window,
    ) -> Option<NativeSize<u32>> {
        self.inner.adjust_size(new_size, window)
    }

    fn set_fallback_scale_factor(
        &self,
        scale_factor: f64,
        window: &Self::Window,
    ) -> Result<(), Self::Error> {
        self.inner.set_fallback_scale_factor(scale_factor, window)
    }

    fn on_virtual_key_from_host(
        &self,
        key_code: VirtualKeyCode,
        is_down: bool,
        modifiers: Modifiers,
    ) -> bool {
        self.inner
            .on_virtual_key_from_host(key_code, is_down, modifiers)
    }

    fn state_changed(&self) {
        self.inner.state_changed();
    }

    fn param_value_changed(&self, id: &str, normalized_value: f32) {
        self.inner.param_value_changed(id, normalized_value);
    }

    fn param_modulation_changed(&self, id: &str, modulation_offset: f32) {
        self.inner.param_modulation_changed(id, modulation_offset);
    }
}
