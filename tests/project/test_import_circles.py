"""No import circle in harness/ (beside the layers contract of pyproject.toml, which checks packages
against each other, not modules within one): two modules that import each other, even only for
type annotations (under TYPE_CHECKING), are one concern in two files, or a third module missing."""
import grimp

def circles(graph) -> list[set[str]]:
    """The strongly connected components of more than one module (Tarjan's algorithm, iterative)."""
    index, low, stack, on_stack, found = {}, {}, [], set(), []
    for root in sorted(graph.modules):
        if root in index:
            continue
        work = [(root, iter(sorted(graph.find_modules_directly_imported_by(root))))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            module, imported = work[-1]
            child = next(imported, None)
            if child is not None:
                if child not in index:
                    index[child] = low[child] = len(index)
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(graph.find_modules_directly_imported_by(child)))))
                elif child in on_stack:
                    low[module] = min(low[module], index[child])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[module])
            if low[module] == index[module]:
                component = set()
                while (member := stack.pop()) != module:
                    component.add(member)
                    on_stack.discard(member)
                on_stack.discard(module)
                if component:
                    found.append(component | {module})
    return found


def test_no_module_of_harness_imports_itself_through_others():
    found = circles(grimp.build_graph("harness", cache_dir=None))
    assert found == [], (
        "import circles (a module importing itself through others; take the shared part into a module "
        f"of its own): {found}")


def test_a_circle_is_found():
    graph = grimp.ImportGraph()
    for module in ("a", "a.b", "a.c", "a.d"):
        graph.add_module(module)
    graph.add_import(importer="a.b", imported="a.c")
    graph.add_import(importer="a.c", imported="a.b")
    graph.add_import(importer="a.c", imported="a.d")
    assert circles(graph) == [{"a.b", "a.c"}]
