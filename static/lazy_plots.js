/* Tells the server which waiting plots have come into view (served as /assets/lazy_plots.js).
 *
 * A new page builds only the plots of its first row; each other plot of the scene waits as
 * an empty pane of its height, marked with the class `fie-plot-pending`
 * (app.explorer: lazy plots). When such a pane comes within MARGIN pixels of the window,
 * its name (`fie-plot-<name>`) is written into the page's hidden text box of class
 * `fie-in-view`, whose value the server reads, builds the plot and draws it. Checked on
 * every scroll and resize (once per frame) and twice a second, for panes that a new scene
 * or a wider window brings into view.
 *
 * Uses only what BokehJS offers a page: `Bokeh.documents`, a model's `css_classes` and
 * `value`. Without it (no BokehJS, no such text box) nothing is reported, and the waiting
 * plots stay empty.
 */
(function () {
  "use strict";

  //: Distance [px] below (and above) the window at which a plot is built: a fast scroll
  //: then finds it drawn.
  const MARGIN = 400;
  const PERIOD_MS = 500;
  let box = null;         // the hidden text box's model
  let plots = null;       // the element of the plots' flex box (app.explorer)
  let queued = false;

  function find(root, cls) {
    // Depth-first through the open shadow roots BokehJS renders into.
    const found = root.querySelector("." + cls);
    if (found) return found;
    for (const el of root.querySelectorAll("*")) {
      if (el.shadowRoot) {
        const inner = find(el.shadowRoot, cls);
        if (inner) return inner;
      }
    }
    return null;
  }

  function textBox() {
    const docs = window.Bokeh && window.Bokeh.documents;
    if (!docs || !docs.length) return null;
    if (box && docs[0].get_model_by_id(box.id) === box) return box;
    box = null;
    for (const m of docs[0].all_models) {
      if (Array.isArray(m.css_classes) && m.css_classes.includes("fie-in-view")) box = m;
    }
    return box;
  }

  function check() {
    queued = false;
    const model = textBox();
    if (model == null) return;
    if (plots == null || !plots.isConnected) plots = find(document, "fie-plots");
    if (plots == null) return;
    const root = plots.shadowRoot || plots;
    const names = [];
    for (const el of root.querySelectorAll(".fie-plot-pending")) {
      const r = el.getBoundingClientRect();
      if (r.width > 0 && r.top < window.innerHeight + MARGIN && r.bottom > -MARGIN) {
        const cls = [...el.classList].find((c) => c.startsWith("fie-plot-") &&
                                                  c !== "fie-plot-pending");
        if (cls) names.push(cls.slice("fie-plot-".length));
      }
    }
    if (!names.length) return;
    const value = names.sort().join(",");
    if (model.value !== value) model.value = value;
  }

  function schedule() {
    if (!queued) {
      queued = true;
      window.requestAnimationFrame(check);
    }
  }

  document.addEventListener("scroll", schedule, {capture: true, passive: true});
  window.addEventListener("resize", schedule, {passive: true});
  setInterval(schedule, PERIOD_MS);
})();
