"""Reports to the user, each distinct message once per render."""


# The warnings of the last final render and of the viewport's last sync, kept for the UI to list
# (Render Properties > SMIS Warnings, the viewport header): Blender's status bar shows a report
# only until the next one replaces it.
recent_warnings = {"render": [], "viewport": []}


class Reporter:
    """Wraps `RenderEngine.report` and drops repeated messages.

    A material used by 500 objects must produce one warning, not 500. One
    Reporter lives as long as the engine instance, i.e. one frame (all view
    layers), which is what "once per render" means here.
    """

    def __init__(self, engine, source="render"):
        self._engine = engine
        self._seen = set()
        self._source = source
        recent_warnings[source] = []
        # Material previews render Blender's own preview scene, whose materials (checker floor)
        # would warn on every thumbnail: they give no warnings.
        self.quiet = False

    def _report(self, kind, message):
        if self.quiet and kind == 'WARNING':
            return
        key = (kind, message)
        if key in self._seen:
            return
        self._seen.add(key)
        if kind == 'WARNING':
            recent_warnings[self._source].append(message)
        if self._engine is not None:
            self._engine.report({kind}, message)
        else:  # used outside a render (tests, scripts)
            print("SMIS %s: %s" % (kind.lower(), message))

    def warning(self, message):
        self._report('WARNING', message)

    def info(self, message):
        self._report('INFO', message)
