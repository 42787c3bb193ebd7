2026-11-25T13:00:57Z `bench/run-all.sh --sizes 512 --scenes oa_dm4 ctf_inyard czest3ctf bunny00 armadillo refined_elephant --frames 3 --threads 1,2`
