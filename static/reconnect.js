/* A page whose server went away says so, and comes back by itself with its state
 * (served as /assets/reconnect.js).
 *
 * A session's document lives in the server process. When that process restarts (a new
 * container, a crash, `--restart unless-stopped`) or the network drops the websocket for
 * longer than the server keeps an unused session, the page's models have no counterpart on
 * the server any more: it still looks normal, but its sliders do nothing. The page keeps
 * its whole state in its address (README, "Links"), so the way back is to reload that
 * address once the server answers again.
 *
 * On BokehJS's `connection_lost` event (`Bokeh.documents[0].on_event`, public API) a banner
 * says so at once (an `aria-live` region, announced by screen readers); the server's
 * liveness endpoint (`panel serve --liveness`, next to the page: `<prefix>/liveness`) is
 * polled with a growing delay; when it answers, the page reloads its own address. The
 * reload waits a random fraction of RELOAD_SPREAD_MS so that a whole class does not open
 * its pages in the same instant after a restart. An answer of the server counts, even 404
 * (a server without --liveness); a proxy's 502/503/504 (no upstream yet) does not.
 * BokehJS's own reconnection and notice are off for the page (app.main): its reconnection
 * would have a restarted server rebuild the page from its first address, racing this reload.
 */
(function () {
  "use strict";

  const MESSAGE = "Connection to the server lost \u2014 reconnecting\u2026";
  const BACK = "The server is back \u2014 reloading the page\u2026";
  const FIRST_DELAY_MS = 500;
  const MAX_DELAY_MS = 5000;
  const REQUEST_TIMEOUT_MS = 4000;
  const RELOAD_SPREAD_MS = 2000;
  const STYLE = [
    "#fie-connection { position: fixed; top: 0; left: 0; right: 0; z-index: 10000;",
    "  padding: 0.6em 1em; font: 600 1rem/1.4 system-ui, sans-serif; text-align: center;",
    "  color: #fff; background: #a4262c; box-shadow: 0 2px 6px rgba(0, 0, 0, 0.35); }",
    "#fie-connection[hidden] { display: none; }",
  ].join("\n");

  let region = null;
  let lost = false;
  let hooked = null;

  function liveRegion() {
    // Created empty at load: a live region must exist before its text changes to be read out.
    if (region) return region;
    const style = document.createElement("style");
    style.textContent = STYLE;
    document.head.appendChild(style);
    region = document.createElement("div");
    region.id = "fie-connection";
    region.setAttribute("role", "alert");
    region.setAttribute("aria-live", "assertive");
    region.hidden = true;
    document.body.appendChild(region);
    return region;
  }

  function say(text) {
    const el = liveRegion();
    el.textContent = text;
    el.hidden = false;
  }

  async function serverAnswers(url) {
    const abort = new AbortController();
    const timer = setTimeout(() => abort.abort(), REQUEST_TIMEOUT_MS);
    try {
      const reply = await fetch(url, { cache: "no-store", signal: abort.signal });
      return reply.status < 502 || reply.status > 504;
    } catch (err) {
      return false;  // refused, reset, timed out: not back yet
    } finally {
      clearTimeout(timer);
    }
  }

  async function waitAndReload() {
    const url = new URL("liveness", window.location.href).href;
    let delay = FIRST_DELAY_MS;
    for (;;) {
      await new Promise((resolve) => setTimeout(resolve, delay));
      if (await serverAnswers(url)) break;
      delay = Math.min(2 * delay, MAX_DELAY_MS);
    }
    say(BACK);
    setTimeout(() => window.location.reload(), Math.random() * RELOAD_SPREAD_MS);
  }

  function onLost() {
    if (lost) return;  // once per page: the reload starts it afresh
    lost = true;
    say(MESSAGE);
    void waitAndReload();
  }

  function hook() {
    const docs = window.Bokeh && window.Bokeh.documents;
    if (docs && docs.length && docs[0] !== hooked) {
      hooked = docs[0];
      liveRegion();
      hooked.on_event("connection_lost", onLost);
    }
  }

  // The document is created after the scripts run; look for it until it is there.
  const finder = setInterval(() => {
    hook();
    if (hooked) clearInterval(finder);
  }, 200);
})();
