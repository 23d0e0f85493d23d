/* The address follows the explorer's state without a browser history entry per change
 * (served as /assets/url_history.js).
 *
 * The explorer keeps its whole state in the page's query string (permalinks; see
 * app.explorer.Explorer.sync_url), and Panel writes each new address with
 * `history.pushState`: every slider release added an entry, so the Back button stepped
 * through each tweak instead of leaving the page. A new address that differs only in its
 * query string or fragment now replaces the current entry; any other address is pushed as
 * before. The address bar always shows the permalink of what is on screen. Panel 1.9's
 * Location has no option to replace the entry. A patch of app.perf.PATCHES
 * (`address-in-place`): applied only where the server names it in this script's address.
 */
(function () {
  "use strict";
  // The patches of this script that the server applies (app.perf.page), named in the
  // script's own address; none without the server's word.
  const script = document.currentScript;
  const APPLY = new Set(((script && new URL(script.src, window.location.href)
    .searchParams.get("apply")) || "").split(",").filter(Boolean));
  if (!APPLY.has("address-in-place")) {
    console.info("url_history.js: address-in-place not applied (app.perf)");
    return;
  }
  const push = window.history.pushState.bind(window.history);
  window.history.pushState = function (state, title, url) {
    if (url != null) {
      const next = new URL(String(url), window.location.href);
      if (next.origin === window.location.origin && next.pathname === window.location.pathname) {
        window.history.replaceState(state, title, url);
        return;
      }
    }
    push(state, title, url);
  };
  (window.__fie_patches = window.__fie_patches || []).push("address-in-place");
})();
