/* Every slider's handle is named after its parameter (served as /assets/a11y.js).
 *
 * BokehJS 3.9 draws a slider with noUiSlider, whose handle carries role="slider" and its
 * value (aria-valuenow, aria-valuetext) but no accessible name: a screen reader announced
 * "slider, 0.3" without saying which of the page's twenty sliders it was. Neither Bokeh's
 * Slider nor Panel's FloatSlider has an option for it. The explorer gives each slider its
 * parameter's label as its title (hidden: the number box above it shows the label), and
 * here each handle gets that title as its aria-label whenever the title is drawn, so the
 * name follows a change of label (e.g. the units of a length in SI mode).
 *
 * Written against BokehJS 3.9's AbstractSliderView (`_update_title`, `slider_el`); if they
 * are missing nothing is changed and the console says so. A patch of app.perf.PATCHES
 * (`slider-handle-names`): applied only where the server names it in this script's address
 * (off with EXPLORER_PERF_PATCHES=off, or outside its Bokeh window).
 */
(function () {
  "use strict";
  // The patches of this script that the server applies (app.perf.page), named in the
  // script's own address; none without the server's word.
  const script = document.currentScript;
  const APPLY = new Set(((script && new URL(script.src, window.location.href)
    .searchParams.get("apply")) || "").split(",").filter(Boolean));

  function name(view) {
    const el = view.slider_el;
    if (el == null) return;
    const title = view.model.title;
    for (const handle of el.querySelectorAll(".noUi-handle")) {
      if (title) handle.setAttribute("aria-label", title);
      else handle.removeAttribute("aria-label");
    }
  }

  function install(B, tries) {
    let sliders;
    try {
      sliders = B.require("models/widgets/sliders/abstract_slider");
    } catch (err) {
      // The widgets bundle registers after BokehJS: try again for a while.
      if (tries > 0) setTimeout(() => install(B, tries - 1), 20);
      return;
    }
    const view = sliders.AbstractSliderView && sliders.AbstractSliderView.prototype;
    if (!view || typeof view._update_title !== "function") {
      console.info(`a11y.js: no AbstractSliderView._update_title in BokehJS ${B.version}: ` +
                   "slider handles stay unnamed");
      return;
    }
    const update = view._update_title;
    view._update_title = function () {
      update.apply(this, arguments);
      name(this);
    };
    window.__fie_a11y = true;
    (window.__fie_patches = window.__fie_patches || []).push("slider-handle-names");
  }

  if (!APPLY.has("slider-handle-names")) {
    console.info("a11y.js: slider-handle-names not applied (app.perf): handles stay unnamed");
    return;
  }

  (function wait() {
    const B = window.Bokeh;
    if (B && typeof B.require === "function") install(B, 500);
    else setTimeout(wait, 5);
  })();
})();
