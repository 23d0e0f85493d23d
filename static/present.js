/* Presentation mode of the explorer (served as /assets/present.js).
 *
 * The server writes `present=1` (one large plot) or `present=4` (2x2) into the page's
 * address (app.presentation) through Panel's Location model; this script gives the body the
 * classes `fie-present` and `fie-present-<layout>` while the address says so, and
 * explorer.css collapses the sidebar and hides the header and readout by them. It follows
 * the Location model's `search` (BokehJS's public change signal) and the Back button
 * (`popstate`). Nothing else changes: leaving the mode (`present=0`) removes the classes.
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
  function apply(search) {
    const mode = new URLSearchParams(search).get("present");
    const on = mode === "1" || mode === "4";
    const body = document.body;
    if (body == null) return;
    body.classList.toggle("fie-present", on);
    body.classList.toggle("fie-present-1", mode === "1");
    body.classList.toggle("fie-present-4", mode === "4");
  }
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
