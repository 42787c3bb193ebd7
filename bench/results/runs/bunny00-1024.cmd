2026-11-25T12:58:50Z `bench/run-all.sh --sizes 1024 --scenes oa_dm4 ctf_inyard czest3ctf bunny00 armadillo refined_elephant --only primary,build --frames 3 --threads 1,2`
