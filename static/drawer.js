/* On a phone the controls are a drawer, closed when the page opens (served as
 * /assets/drawer.js).
 *
 * The page's template (Panel's BootstrapTemplate) puts the controls in a sidebar that its
 * header's toggle button shows and hides (Bootstrap's collapse: the class "show"). Below
 * 700 px (app.page_style.PHONE_MAX_WIDTH; static/explorer.css lays it over the plots) the
 * sidebar starts hidden, so that the page opens on the plots, the phase portrait first;
 * the toggle opens it. Uses only the template's documented elements and Bootstrap's
 * classes; no library internal.
 */
(function () {
  "use strict";
  const PHONE = "(max-width: 700px)";

  function close() {
    if (!window.matchMedia(PHONE).matches) return;
    const sidebar = document.getElementById("sidebar");
    const toggle = document.getElementById("sidebar-toggle");
    if (sidebar == null) return;
    sidebar.classList.remove("show");
    if (toggle != null) {
      toggle.setAttribute("aria-expanded", "false");
      toggle.setAttribute("aria-label", "Show the controls");
    }
  }

  if (document.readyState === "loading") document.addEventListener("DOMContentLoaded", close);
  else close();
})();
