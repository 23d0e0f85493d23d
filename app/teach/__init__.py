"""What a student reads on the page: the model card (mechanism, equations, glossary, details)
and each scene's story, written for a reader who has not seen the paper.

The texts are plain data (:mod:`app.teach.glossary`, :mod:`app.teach.equations`,
:mod:`app.teach.stories`); :mod:`app.teach.view` puts them on the page, each below a button
and built the first time it is pressed, with their mathematics typeset by Bokeh's own
MathJax bundle, which the browser fetches from this server at that moment.
"""
