//! The CLAP GUI extension in the test host: showing the plugin's editor embedded in a window of
//! the host's, the way a DAW on Linux does (X11, not floating).
//!
//! - [`ParentWindow`]: the host's window (an X11 window made with `x11rb` on the test's X
//!   server, see [`crate::xvfb`]);
//! - [`open_editor`] / [`close_editor`]: `create` → `set_scale` → `get_size` → `set_parent` →
//!   `show`, and `hide` → `destroy`; [`resize_editor`] and [`editor_size`] while it is open;
//! - the host side of the extension (`clap_host_gui`): the plugin may ask to be resized, shown
//!   or hidden, and reports when its window closed; the test host agrees and counts.

use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use clack_extensions::gui::{
    GuiApiType, GuiConfiguration, GuiSize, HostGuiImpl, PluginGui, Window,
};
use clack_host::prelude::HostError;
use x11rb::connection::Connection;
use x11rb::protocol::xproto::{
    AtomEnum, ConfigureWindowAux, ConnectionExt, CreateWindowAux, PropMode, WindowClass,
};
use x11rb::rust_connection::RustConnection;
use x11rb::wrapper::ConnectionExt as _;

use crate::clap::{Instance, TestShared};

/// Resize requests the plugins made (any instance; the test host always agrees).
pub static RESIZE_REQUESTS: AtomicU64 = AtomicU64::new(0);
/// "Window closed" notifications from the plugins.
pub static CLOSED_NOTIFICATIONS: AtomicU64 = AtomicU64::new(0);

/// The process's threads just before the last [`open_editor`] (ids, sorted).
static THREADS_BEFORE_OPEN: Mutex<Vec<u32>> = Mutex::new(Vec::new());

/// How long [`close_editor`] waits for the editor's threads to end: generous, for loaded
/// machines.
const THREAD_END_PATIENCE: Duration = Duration::from_secs(10);

/// This process's thread ids, sorted (empty without procfs).
pub fn thread_ids() -> Vec<u32> {
    let mut ids: Vec<u32> = std::fs::read_dir("/proc/self/task")
        .map(|d| {
            d.filter_map(|t| t.ok()?.file_name().to_str()?.parse().ok())
                .collect()
        })
        .unwrap_or_default();
    ids.sort_unstable();
    ids
}

impl HostGuiImpl for TestShared {
    fn resize_hints_changed(&self) {}

    fn request_resize(&self, _new_size: GuiSize) -> Result<(), HostError> {
        RESIZE_REQUESTS.fetch_add(1, Ordering::Relaxed);
        Ok(())
    }

    fn request_show(&self) -> Result<(), HostError> {
        Ok(())
    }

    fn request_hide(&self) -> Result<(), HostError> {
        Ok(())
    }

    fn closed(&self, _was_destroyed: bool) {
        CLOSED_NOTIFICATIONS.fetch_add(1, Ordering::Relaxed);
    }
}

/// The host's window that the editor is embedded in.
pub struct ParentWindow {
    conn: RustConnection,
    /// X11 window id.
    pub id: u32,
}

impl ParentWindow {
    /// Creates and maps a `width`×`height` top-level window on `display` (e.g. ":91").
    pub fn new(display: &str, width: u16, height: u16) -> Result<Self, String> {
        let (conn, screen_num) = x11rb::connect(Some(display)).map_err(|e| e.to_string())?;
        let screen = &conn.setup().roots[screen_num];
        let root = screen.root;
        let black = screen.black_pixel;
        let id = conn.generate_id().map_err(|e| e.to_string())?;
        conn.create_window(
            x11rb::COPY_DEPTH_FROM_PARENT,
            id,
            root,
            0,
            0,
            width,
            height,
            0,
            WindowClass::INPUT_OUTPUT,
            0,
            &CreateWindowAux::new().background_pixel(black),
        )
        .map_err(|e| e.to_string())?;
        conn.map_window(id).map_err(|e| e.to_string())?;
        conn.flush().map_err(|e| e.to_string())?;
        Ok(Self { conn, id })
    }

    /// Resizes the window (as a host does to fit the plugin's size).
    pub fn resize(&self, width: u32, height: u32) -> Result<(), String> {
        self.conn
            .configure_window(
                self.id,
                &ConfigureWindowAux::new().width(width).height(height),
            )
            .map_err(|e| e.to_string())?;
        self.conn.flush().map_err(|e| e.to_string())
    }
}

impl ParentWindow {
    /// Sizes of the windows embedded in this one (the editor's), physical pixels.
    pub fn child_sizes(&self) -> Result<Vec<(u32, u32)>, String> {
        let tree = self
            .conn
            .query_tree(self.id)
            .map_err(|e| e.to_string())?
            .reply()
            .map_err(|e| e.to_string())?;
        let mut out = Vec::new();
        for child in tree.children {
            if let Ok(cookie) = self.conn.get_geometry(child)
                && let Ok(g) = cookie.reply()
            {
                out.push((u32::from(g.width), u32::from(g.height)));
            }
        }
        Ok(out)
    }

    /// Sets the X resource `Xft.dpi` on the server (the root window's `RESOURCE_MANAGER`
    /// property), as a desktop does for a high-DPI screen; windows opened afterwards read it.
    pub fn set_xft_dpi(&self, dpi: u32) -> Result<(), String> {
        let root = self.conn.setup().roots[0].root;
        let atom = self
            .conn
            .intern_atom(false, b"RESOURCE_MANAGER")
            .map_err(|e| e.to_string())?
            .reply()
            .map_err(|e| e.to_string())?
            .atom;
        self.conn
            .change_property8(
                PropMode::REPLACE,
                root,
                atom,
                AtomEnum::STRING,
                format!("Xft.dpi:\t{dpi}\n").as_bytes(),
            )
            .map_err(|e| e.to_string())?;
        self.conn.sync().map_err(|e| e.to_string())
    }
}

impl Drop for ParentWindow {
    fn drop(&mut self) {
        let _ = self.conn.destroy_window(self.id);
        let _ = self.conn.flush();
    }
}

/// Opens the editor embedded in `parent`: create, scale 1, size, parent, show. Returns the size
/// the plugin asked for.
pub fn open_editor(inst: &mut Instance, parent: &ParentWindow) -> Result<GuiSize, String> {
    let h = inst.plugin_handle();
    let gui: PluginGui = h.get_extension().ok_or("no GUI extension")?;
    let config = GuiConfiguration {
        api_type: GuiApiType::X11,
        is_floating: false,
    };
    if !gui.is_api_supported(&h, config) {
        return Err("the plugin does not support embedded X11 windows".into());
    }
    *THREADS_BEFORE_OPEN
        .lock()
        .unwrap_or_else(|e| e.into_inner()) = thread_ids();
    gui.create(&h, config).map_err(|e| format!("create: {e}"))?;
    // Hosts tell the plugin the display scale; on X11 it may refuse (then it asks X).
    let _ = gui.set_scale(&h, 1.0);
    let size = gui.get_size(&h).ok_or("get_size failed")?;
    parent.resize(size.width, size.height)?;
    // SAFETY: the parent window exists until after `close_editor` (the caller owns it).
    unsafe { gui.set_parent(&h, Window::from_x11_handle(u64::from(parent.id) as _)) }
        .map_err(|e| format!("set_parent: {e}"))?;
    gui.show(&h).map_err(|e| format!("show: {e}"))?;
    Ok(size)
}

/// Asks the open editor to take a new size, as a host does when the user resizes its window
/// (and resizes `parent` to match).
pub fn resize_editor(
    inst: &mut Instance,
    parent: &ParentWindow,
    width: u32,
    height: u32,
) -> Result<(), String> {
    let h = inst.plugin_handle();
    let gui: PluginGui = h.get_extension().ok_or("no GUI extension")?;
    if !gui.can_resize(&h) {
        return Err("the editor is not resizable".into());
    }
    parent.resize(width, height)?;
    gui.set_size(&h, GuiSize { width, height })
        .map_err(|e| format!("set_size: {e}"))
}

/// The editor's size as the plugin reports it (physical pixels).
pub fn editor_size(inst: &mut Instance) -> Result<GuiSize, String> {
    let h = inst.plugin_handle();
    let gui: PluginGui = h.get_extension().ok_or("no GUI extension")?;
    gui.get_size(&h).ok_or_else(|| "get_size failed".into())
}

/// Hides and destroys the editor, then waits (up to `THREAD_END_PATIENCE`) until every thread
/// started since [`open_editor`] has ended.
///
/// `destroy` does not always wait for the window's thread: baseview 0.4.2's window handle, when
/// dropped, stops the window's event loop and then asks the window to show itself before it
/// joins the thread, and when the loop has already ended that request fails and the join is
/// skipped. The thread then tears its GL context down (EGL unloading the Mesa driver) on its
/// own, and if the test returns meanwhile, that races the process's exit: a segmentation fault
/// after the test passed (6 of 83 runs of `editor_window_size` on the 2-core host, 2026-11-29; 0 of
/// 120 with this wait). The plugin itself now waits for its window threads when it is destroyed
/// (`plugin/src/editor/window_threads.rs`; 0 of 80 runs crashed with that alone); this wait
/// makes each close end with the threads it started gone, whatever the plugin does.
pub fn close_editor(inst: &mut Instance) -> Result<(), String> {
    let h = inst.plugin_handle();
    let gui: PluginGui = h.get_extension().ok_or("no GUI extension")?;
    gui.hide(&h).map_err(|e| format!("hide: {e}"))?;
    gui.destroy(&h);
    let before = THREADS_BEFORE_OPEN
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .clone();
    let t0 = Instant::now();
    while thread_ids()
        .iter()
        .any(|t| before.binary_search(t).is_err())
        && t0.elapsed() < THREAD_END_PATIENCE
    {
        std::thread::sleep(Duration::from_millis(5));
    }
    Ok(())
}
