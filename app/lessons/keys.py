"""The arrow keys of a lesson: ← for the step before, → for the next.

A key goes to the lesson only when no control has it: a slider's handle, a text box or a
selector moves with the arrows itself. The listener lives on the document while the
component is on the page, and is removed with it.
"""

from __future__ import annotations

import param
from panel.reactive import ReactiveHTML

#: The listener, installed once per page (a component built again replaces it).
_SCRIPT = """
if (window.fieLessonKeys) { document.removeEventListener('keydown', window.fieLessonKeys) }
window.fieLessonKeys = (event) => {
  if (event.altKey || event.ctrlKey || event.metaKey || event.shiftKey) { return }
  if (event.key !== 'ArrowLeft' && event.key !== 'ArrowRight') { return }
  const target = event.composedPath()[0]
  if (target && target.closest) {
    const own = target.closest('input, textarea, select, [role="slider"], [contenteditable]')
    if (own) { return }
  }
  if (event.key === 'ArrowLeft') { data.back = data.back + 1 }
  else { data.forward = data.forward + 1 }
  event.preventDefault()
}
document.addEventListener('keydown', window.fieLessonKeys)
"""


class ArrowKeys(ReactiveHTML):
    """Counts the presses of ← (``back``) and → (``forward``) meant for the lesson."""

    back = param.Integer(default=0)
    forward = param.Integer(default=0)

    _template = '<div id="keys" class="fie-lesson-keys"></div>'
    _scripts = {  # noqa: RUF012 - Panel's declaration of the component's scripts
        "render": _SCRIPT,
        "remove": "document.removeEventListener('keydown', window.fieLessonKeys); "
                  "window.fieLessonKeys = null",
    }
