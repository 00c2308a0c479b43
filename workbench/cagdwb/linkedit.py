"""Link rows of the task panel (taskpanel.py): one widget for every link property,
chosen by the property's type as FreeCAD's own Loft and Sweep panels do. It lists the
current links ("Label.Edge2", "Label" for a whole object); a list (LinkSubList,
LinkList) has "Add selection", "Remove", "Up" and "Down", a single link (LinkSub,
Link) "Set from selection". Each change goes through the panel's ``apply`` (set,
recompute, show the object's Message), so Cancel undoes it with the rest; a selection
that cannot be used (nothing selected, the edited object itself, more than one element
for a single link) is said in the panel's status line and changes nothing. No geometry
here: what a link must be is the object's ``execute`` to say."""
from __future__ import annotations

from typing import Callable, List, Optional, Tuple

import FreeCADGui as Gui
from .qt import QtWidgets

LIST_KINDS = ("App::PropertyLinkSubList", "App::PropertyLinkList")
SINGLE_KINDS = ("App::PropertyLinkSub", "App::PropertyLink")
KINDS = LIST_KINDS + SINGLE_KINDS
LIST_ROWS = 5                   # rows the list shows before it scrolls

Item = Tuple[object, str]       # (object, sub-element name or "" for the whole object)


def items(value) -> List[Item]:
    """The links of a link property's value as (object, sub-element) pairs in order (a
    LinkSubList groups an object's consecutive sub-elements: they are taken apart)."""
    if value is None:
        return []
    if not isinstance(value, list):
        value = [value]
    out: List[Item] = []
    for entry in value:
        if isinstance(entry, tuple):
            obj, subs = entry
            subs = [subs] if isinstance(subs, str) else list(subs or ())
            out.extend((obj, s) for s in (subs or [""]))
        elif entry is not None:
            out.append((entry, ""))
    return out


def value_of(kind: str, links: List[Item]):
    """The property value of ``kind`` holding ``links``."""
    if kind == "App::PropertyLinkSubList":
        return [(o, s) for o, s in links]
    if kind == "App::PropertyLinkList":
        return [o for o, _ in links]
    if not links:
        return None
    obj, sub = links[0]
    return (obj, [sub] if sub else []) if kind == "App::PropertyLinkSub" else obj


def text(item: Item) -> str:
    obj, sub = item
    return f"{obj.Label}.{sub}" if sub else obj.Label


def selection(kind: str, exclude) -> List[Item]:
    """The current selection as links of ``kind`` (a whole-object link kind takes the
    selected objects once each), in selection order, without ``exclude``."""
    out: List[Item] = []
    for sel in Gui.Selection.getSelectionEx():
        if sel.Object is exclude:
            continue
        subs = list(sel.SubElementNames) if kind.startswith("App::PropertyLinkSub") else []
        for sub in subs or [""]:
            if (sel.Object, sub) not in out:
                out.append((sel.Object, sub))
    return out


class LinkEditor(QtWidgets.QWidget):
    """The row of one link property: the links listed, the buttons under them
    (``self.buttons`` by their text). ``apply(value)`` sets the property and
    recomputes; ``say(text)`` shows a refusal in the panel."""

    def __init__(self, obj, name: str, kind: str, apply: Callable, say: Callable[[str], None]):
        super().__init__()
        self.obj, self.name, self.kind, self._apply, self.say = obj, name, kind, apply, say
        layout = QtWidgets.QVBoxLayout(self)
        layout.setContentsMargins(0, 0, 0, 0)
        self.list = QtWidgets.QListWidget()
        rows = LIST_ROWS if kind in LIST_KINDS else 1
        self.list.setMaximumHeight(int(self.list.fontMetrics().height() * (rows + 0.5)) + 2 * self.list.frameWidth())
        layout.addWidget(self.list)
        buttons = QtWidgets.QHBoxLayout()
        actions = (("Add selection", self.add), ("Remove", self.remove), ("Up", lambda: self.move(-1)),
                   ("Down", lambda: self.move(1))) if kind in LIST_KINDS else \
            (("Set from selection", self.set_from_selection),)
        self.buttons = {}
        for label, action in actions:
            button = QtWidgets.QPushButton(label)
            button.clicked.connect(lambda _checked=False, a=action: a())
            buttons.addWidget(button)
            self.buttons[label] = button
        layout.addLayout(buttons)
        self.refresh()

    def links(self) -> List[Item]:
        return items(getattr(self.obj, self.name))

    def refresh(self, current: Optional[int] = None) -> None:
        """List the property's links; select row ``current`` (when given)."""
        self.list.clear()
        self.list.addItems([text(i) for i in self.links()])
        if current is not None and 0 <= current < self.list.count():
            self.list.setCurrentRow(current)

    def write(self, links: List[Item], current: Optional[int] = None) -> None:
        self._apply(self.name, value_of(self.kind, links))
        self.refresh(current)

    def _picked(self) -> List[Item]:
        picked = selection(self.kind, self.obj)
        if not picked:
            self.say(f"{self.name}: nothing selected (select edges, faces or objects in the 3-D view or the tree)")
        return picked

    # --- the buttons ------------------------------------------------------------------------
    def add(self) -> None:
        """Append the selected elements (those not linked yet)."""
        picked = self._picked()
        if not picked:
            return
        links = self.links()
        new = [i for i in picked if i not in links]
        if not new:
            return self.say(f"{self.name}: {', '.join(text(i) for i in picked)} already linked")
        Gui.Selection.clearSelection()
        self.write(links + new, len(links) + len(new) - 1)

    def remove(self) -> None:
        row = self.list.currentRow()
        links = self.links()
        if not 0 <= row < len(links):
            return self.say(f"{self.name}: pick the link to remove in the list")
        del links[row]
        self.write(links, min(row, len(links) - 1))

    def move(self, step: int) -> None:
        row = self.list.currentRow()
        links = self.links()
        if not 0 <= row < len(links) or not 0 <= row + step < len(links):
            return
        links[row], links[row + step] = links[row + step], links[row]
        self.write(links, row + step)

    def set_from_selection(self) -> None:
        picked = self._picked()
        if not picked:
            return
        if len(picked) > 1:
            return self.say(f"{self.name}: select one element (got {', '.join(text(i) for i in picked)})")
        Gui.Selection.clearSelection()
        self.write(picked, 0)
