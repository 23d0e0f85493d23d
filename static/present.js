/* Presentation mode of the explorer (served as /assets/present.js).
 *
 * The server writes `present=1` .. `present=4` (the number of plots) into the page's
 * address (app.presentation) through Panel's Location model; this script gives the body the
 * classes `fie-present` and `fie-present-<layout>` while the address says so, and the page's
 * frame is styled by them (explorer.css collapses the sidebar; FRAME_CSS below hides the
 * header and the main area's padding, so that the plots and the control strip have the whole
 * window). It follows the Location model's `search` (BokehJS's public change signal) and the
 * Back button (`popstate`). Leaving the mode (`present=0`) removes the classes.
 *
 * Keyboard shortcuts (listed in the strip's "?" help, app.present_strip.KEYS_HELP), never
 * while a text box, a selector or a slider has the key: P presents (the sidebar's Present
 * button) or leaves (the strip's Exit), 1-4 pick the layout (the strip's layout buttons),
 * F toggles fullscreen, ? opens the help. Each presses the page's own button, so that the
 * server's state stays the one source of what is shown. The lesson's arrows are the lesson
 * player's own (app.lessons.keys).
 *
 * With `slides=png` the page reports a device pixel ratio of at least PNG_SCALE, so that
 * BokehJS draws its canvases, and its save tool exports them, at that many pixels per CSS
 * pixel (app.presentation.PNG_SCALE); the real ratio returns with the address. BokehJS 3.9
 * has no option for the resolution of a saved figure: this is a patch of app.perf.PATCHES
 * (`slide-pixel-ratio`), applied only where the server names it in this script's address.
 */
(function () {
  "use strict";
  // The patches of this script that the server applies (app.perf.page), named in the
  // script's own address; none without the server's word.
  const script = document.currentScript;
  const APPLY = new Set(((script && new URL(script.src, window.location.href)
    .searchParams.get("apply")) || "").split(",").filter(Boolean));
  const PNG_SCALE = 3;
  if (APPLY.has("slide-pixel-ratio")) {
    const real = Object.getOwnPropertyDescriptor(window, "devicePixelRatio");
    const realRatio = () => (real && real.get ? real.get.call(window) : 1);
    Object.defineProperty(window, "devicePixelRatio", {
      configurable: true,
      get() {
        const slides = new URLSearchParams(window.location.search).get("slides");
        return slides === "png" ? Math.max(realRatio(), PNG_SCALE) : realRatio();
      },
    });
    (window.__fie_patches = window.__fie_patches || []).push("slide-pixel-ratio");
  }
  const LAYOUTS = ["1", "2", "3", "4"];
  // The page's frame while presenting: no header, no padding round the main area.
  const FRAME_CSS = `
body.fie-present #header { display: none !important; }
body.fie-present #main, body.fie-present .main { padding: 0 !important; margin-top: 0 !important; }
body.fie-present #content { padding-top: 0 !important; margin-top: 0 !important; }`;
  function frameStyle() {
    if (document.getElementById("fie-present-frame") || document.head == null) return;
    const style = document.createElement("style");
    style.id = "fie-present-frame";
    style.textContent = FRAME_CSS;
    document.head.appendChild(style);
  }
  function apply(search) {
    const mode = new URLSearchParams(search).get("present");
    const on = LAYOUTS.includes(mode);
    const body = document.body;
    if (body == null) return;
    if (on) frameStyle();
    body.classList.toggle("fie-present", on);
    for (const key of LAYOUTS) body.classList.toggle(`fie-present-${key}`, mode === key);
  }
  // The shadow root of the view of the model with CSS class `cls` (the page's widgets
  // render in shadow DOMs), or null.
  function viewRoot(cls) {
    const index = window.Bokeh && window.Bokeh.index;
    if (index == null || index.query == null) return null;
    for (const view of index.query((v) => v.model != null && v.model.css_classes != null &&
                                          v.model.css_classes.includes(cls))) {
      const root = view.shadow_el || view.el.shadowRoot;
      if (root != null && view.el.isConnected) return root;
    }
    return null;
  }
  function press(cls, nth) {
    const root = viewRoot(cls);
    const buttons = root ? root.querySelectorAll("button") : [];
    const button = buttons[nth || 0];
    if (button == null || button.disabled) return false;
    button.click();
    return true;
  }
  const presenting = () => document.body != null &&
    document.body.classList.contains("fie-present");
  function toggleFullscreen() {
    if (document.fullscreenElement) {
      document.exitFullscreen();
    } else if (document.documentElement.requestFullscreen) {
      document.documentElement.requestFullscreen().catch(() => {});
    }
  }
  function toggleHelp() {
    const root = viewRoot("fie-present-help");
    const details = root && root.querySelector("details");
    if (details) details.open = !details.open;
  }
  function onKey(event) {
    if (event.altKey || event.ctrlKey || event.metaKey) return;
    const target = event.composedPath()[0];
    if (target && target.closest &&
        target.closest('input, textarea, select, [role="slider"], [contenteditable]')) return;
    const key = event.key;
    let done = false;
    if (key === "p" || key === "P") {
      done = presenting() ? press("fie-present-exit") : press("fie-present-button");
    } else if (presenting() && LAYOUTS.includes(key)) {
      done = press("fie-present-layouts", LAYOUTS.indexOf(key));
    } else if (presenting() && (key === "f" || key === "F")) {
      toggleFullscreen();
      done = true;
    } else if (presenting() && key === "?") {
      toggleHelp();
      done = true;
    }
    if (done) event.preventDefault();
  }
  document.addEventListener("keydown", onKey);
  const fromAddress = () => apply(window.location.search);
  // Panel's Location model: the one with the address's parts as properties.
  const isLocation = (m) => m.properties != null && m.properties.search != null &&
    m.properties.pathname != null && m.properties.reload != null;
  let watched = null;
  const finder = setInterval(() => {
    const docs = window.Bokeh && window.Bokeh.documents;
    const doc = docs && docs[0];
    if (!doc || doc === watched) return;
    const location = [...doc.all_models].find(isLocation);
    if (location == null) return;
    watched = doc;
    clearInterval(finder);
    location.properties.search.change.connect(() => apply(location.search));
    apply(location.search);
  }, 50);
  window.addEventListener("popstate", fromAddress);
  if (document.readyState === "loading") {
    document.addEventListener("DOMContentLoaded", fromAddress);
  } else {
    fromAddress();
  }
})();
