/* On a phone the controls are a drawer, closed when the page opens (served as
 * /assets/drawer.js).
 *
 * The page's template (Panel's BootstrapTemplate) puts the controls in a sidebar that its
 * header's toggle button shows and hides (Bootstrap's collapse: the class "show"). Below
 * 700 px (app.page_style.PHONE_MAX_WIDTH; static/explorer.css lays it over the plots) the
 * sidebar starts hidden, so that the page opens on the plots, the phase portrait first;
 * the toggle opens it. The toggle is named after what it shows and hides, at every width.
 * Uses only the template's documented elements and Bootstrap's classes; no library
 * internal.
 */
(function () {
  "use strict";
  const PHONE = "(max-width: 700px)";

  function close() {
    const sidebar = document.getElementById("sidebar");
    const toggle = document.getElementById("sidebar-toggle");
    // The toggle says what it shows and hides (the template calls it "Toggle sidebar").
    if (toggle != null) toggle.setAttribute("aria-label", "Show or hide the controls");
    if (sidebar == null || !window.matchMedia(PHONE).matches) return;
    sidebar.classList.remove("show");
    if (toggle != null) toggle.setAttribute("aria-expanded", "false");
  }

  if (document.readyState === "loading") document.addEventListener("DOMContentLoaded", close);
  else close();
})();
