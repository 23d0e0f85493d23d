/* Presentation mode of the explorer (served as /assets/present.js).
 *
 * The server writes `present=1` (one large plot) or `present=4` (2x2) into the page's
 * address (app.presentation); this script gives the body the classes `fie-present` and
 * `fie-present-<layout>` while the address says so, and explorer.css collapses the sidebar
 * and hides the header and readout by them. Nothing else changes: leaving the mode
 * (`present=0`) removes the classes.
 *
 * With `slides=png` the page reports a device pixel ratio of at least PNG_SCALE, so that
 * BokehJS draws its canvases, and its save tool exports them, at that many pixels per CSS
 * pixel (app.presentation.PNG_SCALE); the real ratio returns with the address.
 */
(function () {
  "use strict";
  const PNG_SCALE = 3;
  const real = Object.getOwnPropertyDescriptor(window, "devicePixelRatio");
  const realRatio = () => (real && real.get ? real.get.call(window) : 1);
  Object.defineProperty(window, "devicePixelRatio", {
    configurable: true,
    get() {
      const slides = new URLSearchParams(window.location.search).get("slides");
      return slides === "png" ? Math.max(realRatio(), PNG_SCALE) : realRatio();
    },
  });
  function apply() {
    const mode = new URLSearchParams(window.location.search).get("present");
    const on = mode === "1" || mode === "4";
    const body = document.body;
    if (body == null) return;
    body.classList.toggle("fie-present", on);
    body.classList.toggle("fie-present-1", mode === "1");
    body.classList.toggle("fie-present-4", mode === "4");
  }
  for (const name of ["pushState", "replaceState"]) {
    const original = window.history[name].bind(window.history);
    window.history[name] = function (state, title, url) {
      original(state, title, url);
      apply();
    };
  }
  window.addEventListener("popstate", apply);
  if (document.readyState === "loading") {
    document.addEventListener("DOMContentLoaded", apply);
  } else {
    apply();
  }
})();
