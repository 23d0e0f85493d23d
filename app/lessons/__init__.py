"""Lessons: guided steps that drive the live page.

A lesson is a Markdown file of this folder (its format: this folder's README.md): each step
a title, a text with mathematics, and the page's state as a permalink query. The page lists
the lessons and steps through one (:mod:`app.lessons.player`), built only when the address
names a lesson or the lessons button is pressed (:mod:`app.lessons.mount`);
``python -m app.lessons check DIR`` checks a folder's lessons as the page reads them
(:mod:`app.lessons.check`).
"""
