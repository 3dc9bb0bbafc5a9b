"""Progress bars of the command line (tqdm, on stderr), and a silent stand-in when they are off."""

import contextlib
import sys


class _Silent:
    n = 0

    def update(self, n=1):
        self.n += n

    def set_postfix_str(self, text):
        pass

    def set_description_str(self, text):
        pass

    def refresh(self):
        pass


@contextlib.contextmanager
def bar(total, unit, desc, enabled=True):
    """A tqdm bar over `total` units, or a silent one when disabled or when tqdm is missing."""
    try:
        from tqdm import tqdm
    except ImportError:
        tqdm = None
    if not enabled or tqdm is None:
        yield _Silent()
        return
    with tqdm(total=total, unit=unit, desc=desc, file=sys.stderr, dynamic_ncols=True) as progress:
        yield progress


class FilterProgress:
    """Feeds a bar of 100 units per step from the job's log: (step, percent, text) calls, as
    batch_job.run_job's on_line gives them. Percent is the filter's own progress callback (pymeshlab
    prints it with each log line when the MeshSet is verbose)."""

    def __init__(self, progress, steps):
        self.progress, self.steps, self.done = progress, steps, 0

    def __call__(self, step, percent, text):
        if step >= len(self.steps):
            target = 100 * len(self.steps)
            label = "saving"
        else:
            target = 100 * step + (percent or 0)
            label = self.steps[step]
        if percent is None and step < len(self.steps):
            target = max(self.done, 100 * step)
        if target > self.done:
            self.progress.update(target - self.done)
            self.done = target
        number = f"{min(step + 1, len(self.steps))}/{len(self.steps)}"
        self.progress.set_description_str(f"[{number}] {(text or label)[:48]}")
