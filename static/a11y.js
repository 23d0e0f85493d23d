/* What a screen reader and the keyboard need from BokehJS's widgets (served as
 * /assets/a11y.js). Four patches of app.perf.PATCHES, each applied only where the server
 * names it in this script's address (off with EXPLORER_PERF_PATCHES=off, or outside its
 * Bokeh window); where the BokehJS internal a patch wraps is missing nothing is changed and
 * the console says so.
 *
 * slider-handle-names: BokehJS 3.9 draws a slider with noUiSlider, whose handle carries
 * role="slider" and its value but no accessible name: a screen reader announced "slider,
 * 0.3" without saying which of the page's twenty sliders it was. Neither Bokeh's Slider nor
 * Panel's FloatSlider has an option for it. The explorer gives each slider its parameter's
 * label as its title (hidden: the number box above it shows the label), and here each
 * handle gets that title as its aria-label whenever the title is drawn
 * (AbstractSliderView._update_title), so the name follows a change of label.
 *
 * slider-aria-values: noUiSlider (15.7, bundled with BokehJS 3.9) writes a handle's
 * aria-valuenow, aria-valuemin and aria-valuemax rounded to one decimal (toFixed(1)) and
 * its aria-valuetext with two: after five presses of ArrowLeft on r = 1 (steps of 0.01) a
 * screen reader read aria-valuenow 0.9 for the 0.95 shown. No option of noUiSlider, Bokeh
 * or Panel sets them. Here, after noUiSlider's own update of a handle (its "update" event,
 * listened to from AbstractSliderView.render), the four attributes get the handle's value
 * and limits in full (12 significant digits: the float noise of a sum of steps goes).
 *
 * help-keys: an input's "?" icon (its description) shows its tooltip on hover and keeps it
 * on a click, but cannot be reached by the keyboard (a div). Here the icon that
 * InputWidgetView._build_description_el makes is a focusable button named "Help on
 * <label>" with the tooltip's text as its description; focus shows the tooltip, Enter or
 * Space keeps it shown (or hides it again), Escape hides it: the icon's own mouse events,
 * sent by the keyboard.
 *
 * control-names: a split menu button (Panel's MenuButton, split=True: "Pin this run" and
 * its arrow) draws its arrow as a second button with no text and no name, announced as
 * "button"; a checkbox draws its label beside the box, not tied to it, announced as
 * "checkbox". Here the arrow that DropdownView.render draws is named "<label>: more
 * choices" and says that it opens a menu, and the box that CheckboxView.render draws is
 * labelled by its label (aria-labelledby: both in the widget's shadow root).
 */
(function () {
  "use strict";
  // The patches of this script that the server applies (app.perf.page), named in the
  // script's own address; none without the server's word.
  const script = document.currentScript;
  const APPLY = new Set(((script && new URL(script.src, window.location.href)
    .searchParams.get("apply")) || "").split(",").filter(Boolean));
  // Significant digits of an aria value (a step's sum without its float noise).
  const DIGITS = 12;

  function name(view) {
    const el = view.slider_el;
    if (el == null) return;
    const title = view.model.title;
    for (const handle of el.querySelectorAll(".noUi-handle")) {
      if (title) handle.setAttribute("aria-label", title);
      else handle.removeAttribute("aria-label");
    }
  }

  function exact(value) {
    return String(Number(Number(value).toPrecision(DIGITS)));
  }

  const valued = new WeakSet();

  function values(view) {
    const slider = view._noUiSlider;
    if (slider == null || valued.has(slider)) return;
    valued.add(slider);
    slider.on("update.fie-aria", (_, __, unencoded) => {
      const handles = view.slider_el.querySelectorAll(".noUi-handle");
      const {min, max} = slider.options.range;
      handles.forEach((handle, i) => {
        const low = i > 0 ? unencoded[i - 1] : min;
        const high = i < unencoded.length - 1 ? unencoded[i + 1] : max;
        handle.setAttribute("aria-valuemin", exact(Array.isArray(low) ? low[0] : low));
        handle.setAttribute("aria-valuemax", exact(Array.isArray(high) ? high[0] : high));
        handle.setAttribute("aria-valuenow", exact(unencoded[i]));
        handle.setAttribute("aria-valuetext", exact(unencoded[i]));
      });
    });
  }

  function plain(html) {
    // DOMParser runs no script of what it parses.
    const text = Array.isArray(html) ? html.filter((h) => typeof h === "string").join(" ")
      : String(html == null ? "" : html);
    return new DOMParser().parseFromString(text, "text/html").body.textContent.trim();
  }

  function helpText(model) {
    const description = model.description;
    if (description == null) return "";
    if (typeof description === "string") return description;
    const content = description.content;
    if (content == null) return "";
    return typeof content === "string" ? content : plain(content.html);
  }

  function send(el, type) {
    el.dispatchEvent(new MouseEvent(type, {bubbles: true, composed: true}));
  }

  function keys(view, el) {
    if (el == null) return el;
    el.tabIndex = 0;
    el.setAttribute("role", "button");
    const title = typeof view.model.title === "string" ? view.model.title : "";
    el.setAttribute("aria-label", title ? `Help on ${title}` : "Help");
    const text = helpText(view.model);
    if (text) el.setAttribute("aria-description", text);
    el.addEventListener("focus", () => send(el, "mouseenter"));
    el.addEventListener("blur", () => send(el, "mouseleave"));
    el.addEventListener("keydown", (event) => {
      if (event.key === "Enter" || event.key === " ") {
        event.preventDefault();
        send(el, "mousedown");  // shows it to stay, or hides it again
      } else if (event.key === "Escape") {
        send(document.body, "mousedown");  // a press elsewhere hides it
      }
    });
    return el;
  }

  function wrap(proto, member, patch, after) {
    const original = proto && proto[member];
    if (typeof original !== "function") {
      console.info(`a11y.js: no ${member} in BokehJS ${window.Bokeh.version}: ` +
                   `${patch} not applied`);
      return false;
    }
    return after(original);
  }

  function done(patch) {
    (window.__fie_patches = window.__fie_patches || []).push(patch);
  }

  function install(B, tries) {
    let sliders, inputs, dropdowns, checkboxes;
    try {
      sliders = B.require("models/widgets/sliders/abstract_slider");
      inputs = B.require("models/widgets/input_widget");
      dropdowns = B.require("models/widgets/dropdown");
      checkboxes = B.require("models/widgets/checkbox");
    } catch (err) {
      // The widgets bundle registers after BokehJS: try again for a while.
      if (tries > 0) setTimeout(() => install(B, tries - 1), 20);
      return;
    }
    const slider = sliders.AbstractSliderView && sliders.AbstractSliderView.prototype;
    const input = inputs.InputWidgetView && inputs.InputWidgetView.prototype;
    const dropdown = dropdowns.DropdownView && dropdowns.DropdownView.prototype;
    const checkbox = checkboxes.CheckboxView && checkboxes.CheckboxView.prototype;
    if (APPLY.has("slider-handle-names") && wrap(slider, "_update_title",
        "slider-handle-names", (update) => {
          slider._update_title = function () {
            update.apply(this, arguments);
            name(this);
          };
          return true;
        })) {
      window.__fie_a11y = true;
      done("slider-handle-names");
    }
    if (APPLY.has("slider-aria-values") && wrap(slider, "render", "slider-aria-values",
        (render) => {
          slider.render = function () {
            render.apply(this, arguments);
            values(this);
          };
          return true;
        })) done("slider-aria-values");
    if (APPLY.has("help-keys") && wrap(input, "_build_description_el", "help-keys",
        (build) => {
          input._build_description_el = function () {
            return keys(this, build.apply(this, arguments));
          };
          return true;
        })) done("help-keys");
    if (APPLY.has("control-names") &&
        wrap(dropdown, "render", "control-names", (render) => {
          dropdown.render = function () {
            render.apply(this, arguments);
            const label = typeof this.model.label === "string" ? this.model.label : "";
            for (const toggle of this.shadow_el.querySelectorAll(".bk-dropdown-toggle")) {
              toggle.setAttribute("aria-label", label ? `${label}: more choices`
                                                      : "More choices");
              toggle.setAttribute("aria-haspopup", "menu");
            }
          };
          return true;
        }) &&
        wrap(checkbox, "render", "control-names", (render) => {
          checkbox.render = function () {
            render.apply(this, arguments);
            if (this.label_el == null || this.checkbox_el == null) return;
            this.label_el.id = "fie-checkbox-label";
            this.checkbox_el.setAttribute("aria-labelledby", "fie-checkbox-label");
          };
          return true;
        })) done("control-names");
  }

  if (APPLY.size === 0) {
    console.info("a11y.js: no patch applied (app.perf): slider handles stay unnamed, " +
                 "their aria values rounded, the help icons out of the keyboard's reach, a menu's " +
                 "arrow and the checkboxes unnamed");
    return;
  }

  (function wait() {
    const B = window.Bokeh;
    if (B && typeof B.require === "function") install(B, 500);
    else setTimeout(wait, 5);
  })();
})();
