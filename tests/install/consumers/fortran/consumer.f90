! A Fortran host of the installed pnc material plugin (tests/install/check.sh): calls
! umat (gfortran: the symbol umat_) with the standard Abaqus/Standard argument list, NTENS = 6
! (Abaqus order 11, 22, 33, 12, 13, 23; engineering shear; Pa). PROPS are read from the file
! given as argument 1: NPROPS, then PROPS(1) = 1 (model pnc) and the 22 constants C11 C22 C33
! C12 C13 C23 C44 C55 C66 A1 ... alpha (docs/plugin.md "PROPS"), written by the test from the
! installed `pnc card show --json`. Checks, against references computed here from PROPS:
!  1. elastic range (strains <= 0.5 %, far below the onset stretch alpha x 1.2445):
!     STRESS = C0 STRAN and DDSDDE = C0, C0 in Abaqus order (12 -> C66, 13 -> C55, 23 -> C44);
!  2. uniaxial strain 0.15 along x1, past the onset, then unloading to zero: once damage has
!     grown, STRESS = eps/eps_peak x STRESS_peak (damaged secant), STATEV frozen, and the
!     first column of DDSDDE = STRESS_peak / eps_peak.
! Tolerances are rounding bounds (1e-12 of the stress scale). Exit status 0 only if all pass.
program consumer
  implicit none
  integer, parameter :: dp = kind(1.0d0), ntens = 6, nstatv = 6, maxp = 32
  real(dp) :: props(maxp), c0(ntens, ntens), stress(ntens), statev(nstatv), ddsdde(ntens, ntens)
  real(dp) :: stran(ntens), dstran(ntens), dir(ntens), speak(ntens), vpeak(nstatv), want(ntens)
  real(dp) :: scale, tol, r, epeak, smax
  integer :: nprops, k, i, j, n, failures, u
  character(len=512) :: path

  failures = 0
  call get_command_argument(1, path)
  open (newunit=u, file=trim(path), status='old', action='read')
  read (u, *) nprops
  read (u, *) (props(i), i=1, nprops)
  close (u)
  if (nprops /= 23 .or. nint(props(1)) /= 1) then
    print *, 'FAIL: expected NPROPS = 23 and PROPS(1) = 1 (pnc), got', nprops, props(1)
    stop 1
  end if

  ! [C0] in Abaqus order from PROPS(2..10) = C11 C22 C33 C12 C13 C23 C44 C55 C66
  c0 = 0
  c0(1, 1) = props(2); c0(2, 2) = props(3); c0(3, 3) = props(4)
  c0(1, 2) = props(5); c0(2, 1) = props(5)
  c0(1, 3) = props(6); c0(3, 1) = props(6)
  c0(2, 3) = props(7); c0(3, 2) = props(7)
  c0(6, 6) = props(8)  ! 23 <- C44
  c0(5, 5) = props(9)  ! 13 <- C55
  c0(4, 4) = props(10) ! 12 <- C66
  scale = maxval(abs(c0)) * 5e-3_dp

  ! 1. elastic range
  dir = [5e-3_dp, -1e-3_dp, 2e-3_dp, 2.5e-3_dp, 4e-3_dp, -3e-3_dp]
  n = 20
  call reset()
  do k = 1, n
    dstran = dir / n
    call increment()
    stran = stran + dstran
    want = matmul(c0, stran)
    tol = 1e-12_dp * 6 * scale
    do i = 1, ntens
      call check(abs(stress(i) - want(i)) <= tol, 'elastic STRESS = C0 STRAN', stress(i), want(i))
      do j = 1, ntens
        call check(abs(ddsdde(i, j) - c0(i, j)) <= 1e-12_dp * maxval(abs(c0)), &
                   'elastic DDSDDE = C0', ddsdde(i, j), c0(i, j))
      end do
    end do
    do i = 4, 6
      call check(statev(i) == 0, 'no damage in the elastic range', statev(i), 0.0_dp)
    end do
  end do

  ! 2. past the onset, then unloading on the damaged secant
  n = 150
  call reset()
  dstran = 0
  dstran(1) = 0.15_dp / n
  do k = 1, n
    call increment()
    stran = stran + dstran
  end do
  speak = stress
  vpeak = statev
  epeak = stran(1)
  smax = maxval(abs(speak))
  call check(vpeak(4) > 1e-3_dp, 'damage D1 has grown past the onset', vpeak(4), 1e-3_dp)
  dstran(1) = -0.15_dp / n
  do k = 1, n
    call increment()
    stran = stran + dstran
    r = stran(1) / epeak
    do i = 1, ntens
      call check(abs(stress(i) - r * speak(i)) <= 1e-12_dp * smax, 'unloading on the secant', &
                 stress(i), r * speak(i))
      call check(abs(ddsdde(i, 1) - speak(i) / epeak) <= 1e-10_dp * smax / epeak, &
                 'unloading DDSDDE = secant', ddsdde(i, 1), speak(i) / epeak)
    end do
    do i = 1, nstatv
      call check(statev(i) == vpeak(i), 'STATEV frozen while unloading', statev(i), vpeak(i))
    end do
  end do
  print '(a, es14.6, a, f8.4)', 'peak: STRESS(1) =', speak(1), ' Pa, D1 =', vpeak(4)

  if (failures > 0) then
    print *, failures, 'check(s) failed'
    stop 1
  end if
  print '(a)', 'fortran consumer: all checks passed'

contains

  subroutine reset()
    stress = 0; statev = 0; stran = 0 ! Abaqus starts STATEV at zero (= virgin state)
  end subroutine reset

  ! One UMAT call with every argument of the Abaqus/Standard interface.
  subroutine increment()
    real(dp) :: sse, spd, scd, rpl, ddsddt(ntens), drplde(ntens), drpldt, time(2), dtime, &
                temp, dtemp, predef(1), dpred(1), coords(3), drot(3, 3), pnewdt, celent, &
                dfgrd0(3, 3), dfgrd1(3, 3)
    integer :: ndi, nshr, ntens_, nstatv_, nprops_, noel, npt, layer, kspt, kstep, kinc
    character(len=80) :: cmname
    external :: umat
    sse = 0; spd = 0; scd = 0; rpl = 0; ddsddt = 0; drplde = 0; drpldt = 0
    time = 0; dtime = 1; temp = 293; dtemp = 0; predef = 0; dpred = 0; coords = 0
    drot = 0; drot(1, 1) = 1; drot(2, 2) = 1; drot(3, 3) = 1
    pnewdt = 1; celent = 1; dfgrd0 = drot; dfgrd1 = drot
    ndi = 3; nshr = 3; ntens_ = ntens; nstatv_ = nstatv; nprops_ = nprops
    noel = 1; npt = 1; layer = 1; kspt = 1; kstep = 1; kinc = 1
    cmname = 'PNC'
    call umat(stress, statev, ddsdde, sse, spd, scd, rpl, ddsddt, drplde, drpldt, stran, &
              dstran, time, dtime, temp, dtemp, predef, dpred, cmname, ndi, nshr, ntens_, &
              nstatv_, props, nprops_, coords, drot, pnewdt, celent, dfgrd0, dfgrd1, noel, &
              npt, layer, kspt, kstep, kinc)
    if (pnewdt < 1) then
      print *, 'FAIL: umat asked for a smaller increment (PNEWDT =', pnewdt, ')'
      stop 1
    end if
  end subroutine increment

  subroutine check(ok, what, got, expected)
    logical, intent(in) :: ok
    character(len=*), intent(in) :: what
    real(dp), intent(in) :: got, expected
    if (.not. ok) then
      print '(3a, es24.16, a, es24.16)', 'FAIL ', what, ': got ', got, ', want ', expected
      failures = failures + 1
    end if
  end subroutine check

end program consumer
