"""The sweep engine: the job sent to workers (:mod:`.job`), where it runs (:mod:`.backends`:
serial, local processes, Dask), checkpoints and resume (:mod:`.checkpoint`), threads per
process (:mod:`.threads`) and the option objects of :func:`periodyn.sweep` (:mod:`.options`).
:mod:`.front` (:func:`periodyn.sweep`) is the thin front that puts them together; :mod:`.server`
keeps a warm process that runs ``periodyn sweep`` commands (``periodyn serve``)."""
