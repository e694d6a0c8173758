// mipcast piece: refusal
// fills: Terminate::Init
// mode: augment
// A mipcast mapper that refuses to render (bad input, a limit exceeded; the
// reason goes to VTK's error output) sets u_mc_refused: no ray is cast and
// the volume draws nothing, rather than a wrong picture.
  if (u_mc_refused > 0.5)
  {
    discard;
  }
