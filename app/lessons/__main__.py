"""``python -m app.lessons check DIR`` (:mod:`app.lessons.check`)."""

import sys

from app.lessons.check import main

sys.exit(main())
