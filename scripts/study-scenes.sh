# The study's 25 scenes, sourced by scripts/run-studies.sh and scripts/ears-study.sh (`all`), so that both run the
# same list: `boxes`, the six Cornell-style boxes (the built-in one by name, the rest as paths from the repository
# root), and `regime`, the regime scenes (a glossy sphere and floor under a small or a large area light, a smooth
# sky, or the sky with a sun, at n = 1, 10, 100, 1000; two albedo variants; the Stanford bunny).
boxes=(cornell scenes/cornell-diffuse.json scenes/cornell-glossy-100.json scenes/cornell-glossy-1000.json
       scenes/cornell-all-glossy.json scenes/mcguire-glossy.json)
regime=()
for light in small large sky sun; do
  for n in 1 10 100 1000; do regime+=("scenes/regime/$light-n$n.json"); done
done
regime+=(scenes/regime/albedo-diffuse.json scenes/regime/albedo-specular.json scenes/regime/bunny.json)
