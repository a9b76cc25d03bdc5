{-# OPTIONS_GHC -O2 #-}
-- (the fast path is worth optimising even in a --fast build, as Stref.Eval)
{-# LANGUAGE MagicHash #-}
{-# LANGUAGE RankNTypes #-}

-- | A faster evaluator of IEC scan cycles, for a slice of the language,
-- checked against the readable one ("Stref.IEC.Eval", which stays the
-- definition): @fastCycle pol prog@ gives, for a program inside the slice,
-- a function that computes exactly what @runCycle pol prog@ computes (the
-- same machine, the same stop with its position and fault) for an untraced
-- machine; Nothing outside the slice, where the caller runs the readable
-- evaluator.
--
-- How: the checked program is translated ONCE into closures (the style of
-- "Stref.Eval"). Every variable is resolved to a slot of a flat mutable
-- vector when the closures are built: an elementary value is one slot, a
-- structure, an array or a user FB instance lays its parts out one after
-- the other ('Shape'), a standard FB instance with a twin
-- ("Stref.IEC.Fast.StandardFB") lays out its variables too, any other is
-- one slot holding its whole instance, handed to its 'Native' meaning as it
-- is. Each cycle (or batch of cycles) loads the machine's values into the
-- slots, runs the closures in 'ST' and rebuilds the machine from the slots.
-- No rule is restated here: operators, conversions, standard functions,
-- stores into a declared type, index checks, FOR's steps and the watchdog
-- are the functions the readable evaluator calls (exported by
-- "Stref.IEC.Eval" for that), called in the same order and at the same
-- places, so that the results agree by construction; where a case needs no
-- policy, "Stref.IEC.Fast.Operators" computes it on 'Int' and
-- test/IEC/FastOperatorsSpec.hs checks it against those functions; an
-- expression of a small type (an integer of at most 32 bits, BOOL, TIME)
-- is computed on 'Int' the same way and boxed where it is stored or
-- handed on ('intExpr').
-- test/IEC/FastSpec.hs checks the whole on the corpus and on generated
-- programs.
--
-- The slice: elementary types, strings and enumerations, pointers, arrays
-- and structures of them, globals and program instance variables, standard
-- FB instances, user FUNCTION_BLOCKs (with EXTENDS) and FUNCTIONs without
-- VAR_IN_OUT or edge inputs, methods (virtual and SUPER^ calls), THIS, the
-- implicit check functions but CheckPointer; assignment, FB, function and
-- method calls (with @=>@ outputs), IF, CASE, FOR, WHILE, REPEAT, EXIT,
-- RETURN, CONTINUE inside a loop, JMP and labels, ADR and @^@ on the
-- globals and program instances. Not in it: located variables and
-- VAR_CONFIG, pointers into a function's frame or a direct-address area,
-- references to characters and bits, CheckPointer, actions, CODESYS's MUX
-- and SEL (which evaluate only the selected input), chained assignments,
-- program calls. A machine of an unexpected shape, or a pointer the slice
-- does not follow, makes the cycle run in the readable evaluator.
--
-- Pointers: an address is the readable evaluator's (the memory model of
-- "Stref.IEC.Memory"): ADR finds the path of its slot from the root and
-- asks 'offsetOf'; @^@ asks 'locate' for the path at the address, as the
-- readable @variableAt@ does, and follows it in the slots.
module Stref.IEC.Fast
  ( fastCycle
  , fastCycleOnly
  , fastCycles
  ) where

import Control.Monad (forM, forM_, join, when)
import Control.Exception (Exception, throwIO, try)
import Control.Monad.ST (runST)
import Control.Monad.ST.Unsafe (unsafeIOToST, unsafeSTToIO)
import GHC.Exts (Int (I#))
import GHC.ST (ST (..))
import GHC.Num (Integer (IS))
import Data.Bits (xor, (.&.), (.|.))
import Data.Foldable (foldlM)
import Data.List (find)
import qualified Data.IntMap.Lazy as IM
import Data.Maybe (fromMaybe, listToMaybe)
import qualified Data.Map as LM
import qualified Data.Map.Strict as M
import qualified Data.Sequence as Seq
import Data.STRef
import Data.Text (Text)
import qualified Data.Vector as V
import qualified Data.Vector.Mutable as MV
import qualified Data.Vector.Unboxed.Mutable as MU
import Stref.IEC.Checked
import Stref.IEC.Conversions (truncTo)
import Stref.IEC.Eval
import Stref.IEC.Fast.Operators (Binary (..), Convert (..), IntCase (..), Store (..), binaryOn, boolValue, convertOn, intCase, storeOn, storing)
import Stref.IEC.Fast.StandardFB (Twin (..), twin, twinNames)
import Stref.IEC.Memory (Layout, areaAt, locate, offsetOf, sizeInBytes)
import Stref.IEC.Operators (binary, rangeUnder, strip, unary, wrapUnder)
import Stref.IEC.Standard (standard, timeFunction)
import Stref.IEC.Syntax (BinOp (..), Pos (..), PouKind (..), Section (..), UnOp (..))
import Stref.IEC.Types
import Stref.IEC.Values
import Stref.Policy

------------------------------------------------------------------------------
-- Where values lie

-- | How a variable of a type lies in the slots.
data Shape
  = Leaf -- ^ an elementary value, a string, an enumerated value: one slot
  | Opaque -- ^ a standard FB instance: one slot, its whole 'VInstance'
  | Record !(Maybe Text) !(M.Map Text (Int, Shape)) !Int
  -- ^ a structure (Nothing) or an instance of the named POU: its variables
  -- by key, each at an offset; the size
  | Array ![(Integer, Integer)] !Shape !Int !Int -- ^ bounds, the element's shape and size, the number of elements

isLeaf :: Shape -> Bool
isLeaf = \case
  Leaf -> True
  _ -> False

size :: Shape -> Int
size = \case
  Leaf -> 1
  Opaque -> 1
  Record _ _ n -> n
  Array _ _ esz n -> esz * n

-- | Only data: no FB instance inside (such a value can be read and
-- written whole).
isData :: Shape -> Bool
isData = \case
  Leaf -> True
  Opaque -> False
  Record Nothing fs _ -> all (isData . snd) (M.elems fs)
  Record {} -> False
  Array _ e _ _ -> isData e

record :: Maybe Text -> [(Text, Shape)] -> Shape
record name fields =
  let offs = scanl (+) 0 (map (size . snd) fields)
   in Record name (M.fromList [(k, (o, s)) | ((k, s), o) <- zip fields offs]) (last offs)

shapeOf :: Program -> Type -> Maybe Shape
shapeOf prog = \case
  TElem _ -> Just Leaf
  TString _ _ -> Just Leaf
  TEnum _ _ -> Just Leaf
  TSubrange {} -> Just Leaf
  TNumEnum {} -> Just Leaf
  TPointer _ -> Just Leaf -- an address, a DWORD value
  TArray bs t -> do
    e <- shapeOf prog t
    Just (Array bs e (size e) (fromInteger (product [hi - lo + 1 | (lo, hi) <- bs])))
  TStruct _ fs -> record Nothing <$> mapM (\(n, t) -> (key n,) <$> shapeOf prog t) fs
  TFB n -> do
    d <- lookupPou prog n
    case pdBody d of
      -- a standard FB with a twin ("Stref.IEC.Fast.StandardFB") has its
      -- variables, hidden ones included, in slots; the others keep their map
      Native _
        | key (pdName d) `elem` twinNames -> record (Just (pdName d)) <$> mapM (\v -> (viKey v,) <$> shapeOf prog (viType v)) (pdVars d)
        | otherwise -> Just Opaque
      Statements _ -> pouShape prog d
  _ -> Nothing

-- | A POU's variables as an instance or a frame lays them out; Nothing
-- for what the slice leaves out.
pouShape :: Program -> PouDef -> Maybe Shape
pouShape prog d = do
  -- a derived FB's variables start with its base's, so that the base's
  -- code finds them at the same offsets in an instance of either
  let vars = pdVars d
  when (any (\v -> viSection v == SecInOut || viEdge v /= Nothing) vars) Nothing
  record (Just (pdName d)) <$> mapM (\v -> (viKey v,) <$> shapeOf prog (viType v)) vars

-- | Put a value into the slots; False when its shape is not the expected one.
load :: MV.MVector s Value -> Int -> Shape -> Value -> ST s Bool
load vec off sh v = case (sh, v) of
  (Leaf, _) -> True <$ MV.write vec off v
  (Opaque, VInstance {}) -> True <$ MV.write vec off v
  (Record _ fs _, VStruct m) -> fields fs m
  (Record _ fs _, VInstance _ m) -> fields fs m
  (Array bs e esz n, VArray bs' xs)
    | bs == bs' && Seq.length xs == n ->
        foldlM (\ok (i, x) -> if ok then load vec (off + i * esz) e x else pure False) True (zip [0 ..] (foldr (:) [] xs))
  _ -> pure False
  where
    fields fs m
      | M.keys fs == M.keys m = foldlM (\ok ((o, s), x) -> if ok then load vec (off + o) s x else pure False) True (M.elems (M.intersectionWith (,) fs m))
      | otherwise = pure False

-- | A value rebuilt from the slots, on the pattern of the value loaded.
rebuild :: MV.MVector s Value -> Int -> Shape -> Value -> ST s Value
rebuild vec off sh old = case (sh, old) of
  (Record _ fs _, VStruct m) -> VStruct <$> M.traverseWithKey (field fs) m
  (Record _ fs _, VInstance n m) -> VInstance n <$> M.traverseWithKey (field fs) m
  (Array _ e esz _, VArray bs xs) -> VArray bs <$> Seq.traverseWithIndex (\i -> rebuild vec (off + i * esz) e) xs
  _ -> MV.read vec off
  where
    field fs k x = maybe (pure x) (\(o, s) -> rebuild vec (off + o) s x) (M.lookup k fs)

-- | A value built from the slots alone (data only).
build :: MV.MVector s Value -> Int -> Shape -> ST s Value
build vec off = \case
  Record name fs _ -> do
    m <- M.fromDistinctAscList <$> forM (M.toAscList fs) (\(k, (o, s)) -> (k,) <$> build vec (off + o) s)
    pure (maybe (VStruct m) (`VInstance` m) name)
  Array bs e esz n -> VArray bs . Seq.fromList <$> forM [0 .. n - 1] (\i -> build vec (off + i * esz) e)
  _ -> MV.read vec off

------------------------------------------------------------------------------
-- The running machine

data Env s = Env
  { eStore :: !(MV.MVector s Value) -- ^ globals and program instances
  , eSelf :: !(MV.MVector s Value) -- ^ the slots of the running POU's instance or frame
  , eBase :: !Int -- ^ where in them its variables start
  , eThis :: !(MV.MVector s Value) -- ^ the instance THIS names (the readable cxThis): its slots,
  , eThisBase :: !Int -- ^ where it starts,
  , eThisType :: !Text -- ^ and its type's key, which a virtual call dispatches on
  , eDepth :: !Int -- ^ the nesting of calls (the readable evaluator's cxDepth)
  , eSteps :: !(MU.MVector s Int) -- ^ the watchdog's count (mSteps)
  , eFrames :: !(STRef s [(Int, Shape, Value, MV.MVector s Value)])
  -- ^ the frames of the function calls under way (mFrames): depth, shape,
  -- the initial frame (the pattern to rebuild it on), slots
  , eClock :: !Integer
  }

-- | Why the closures stopped: a runtime error, or something the slice did
-- not expect (the cycle then runs in the readable evaluator).
data Abort = Faulted !Pos !Fault | Bail

-- | An abort travels as an exception inside the cycle's 'ST' run (which
-- 'fastCycles' catches), so that the closures pass plain values and no
-- 'Either' is built at every step.
newtype Aborted = Aborted Abort

instance Show Aborted where
  show _ = "Stref.IEC.Fast: an aborted cycle"

instance Exception Aborted

newtype M s a = M {unM :: Env s -> ST s a}

-- | fmap and <*> are strict in the result: every value the closures
-- compute is needed, and a lazy result would build a thunk at each step.
instance Functor (M s) where
  fmap f (M m) = M (\e -> m e >>= \x -> pure $! f x)
  {-# INLINE fmap #-}

instance Applicative (M s) where
  pure x = M (\_ -> pure x)
  {-# INLINE pure #-}
  M mf <*> M mx = M (\e -> mf e >>= \f -> mx e >>= \x -> pure $! f x)
  {-# INLINE (<*>) #-}

instance Monad (M s) where
  M m >>= k = M $ \e -> m e >>= \x -> unM (k x) e
  {-# INLINE (>>=) #-}

st :: ST s a -> M s a
st act = M (\_ -> saturated act)
{-# INLINE st #-}

-- | An action called with the state at once: where the action is a
-- closure not known here, GHC would otherwise make a partial call of it
-- and apply the result to the state (a closure built at every call).
saturated :: ST s a -> ST s a
saturated (ST m) = ST (\s -> m s)
{-# INLINE saturated #-}

env :: M s (Env s)
env = M pure

-- | The closures under another environment (the environment built before
-- they run: a lazy one would be a thunk at every call).
within :: (Env s -> Env s) -> M s a -> M s a
within f (M m) = M (\e -> let !e' = f e in saturated (m e'))

abort :: Abort -> M s a
abort a = M (\_ -> unsafeIOToST (throwIO (Aborted a)))

-- | Run closures; Left where they aborted.
attempt :: M s a -> Env s -> ST s (Either Abort a)
attempt (M m) e = unsafeIOToST (either (\(Aborted a) -> Left a) Right <$> try (unsafeSTToIO (m e)))

orFault :: Pos -> Either Fault a -> M s a
orFault p = \case
  Right x -> x `seq` pure x
  Left f -> abort (Faulted p f)

-- | The readable evaluator's @tick@: one step of the watchdog's budget
-- (TC-ERR-1), at the same places.
tick :: Policies -> Int -> Pos -> M s ()
tick pol budget p = M $ \e -> do
  n <- MU.unsafeRead (eSteps e) 0
  if n >= budget
    then unM (abort (Faulted p (watchdogFault pol budget))) e
    else MU.unsafeWrite (eSteps e) 0 (n + 1)

-- | The checks every call makes (@call-depth@).
deeper :: Policies -> Pos -> M s ()
deeper pol p = M $ \e ->
  if eDepth e >= pCallDepth pol
    then unM (abort (Faulted p (Fault "call-depth" "calls nest too deeply"))) e
    else pure ()

-- | A store into a target of a declared type (the readable @fitValue@
-- without check functions, which the slice leaves out).
fit :: Store -> Pos -> Value -> M s Value
fit store p v = case storing store v of
  Right x -> x `seq` pure x
  Left f -> abort (Faulted p f)

-- | A store into a target of a declared type, with the check function of a
-- subrange where one applies (the readable @fitValue@).
data Fitter = Fitter !(forall s. Value -> M s Value)

-- | An implicit check function's call: its inputs' values, its result.
data Checker = Checker !(forall s. [Value] -> M s Value)

------------------------------------------------------------------------------
-- Places

-- | Where a variable lies now: slots, or a variable of a standard FB
-- instance (which lives in the instance's map).
data Place s = Slot !(MV.MVector s Value) !Int | InFB !(MV.MVector s Value) !Int !Text

data Ref = Ref !(forall s. M s (Place s))

readPlace :: Shape -> Place s -> M s Value
readPlace sh = \case
  Slot v o | not (isLeaf sh) -> st (build v o sh)
  pl -> readLeaf pl

-- | 'readPlace' of an elementary value.
readLeaf :: Place s -> M s Value
readLeaf = \case
  Slot v o -> st (MV.read v o)
  -- a missing variable reads as the readable getPath's default
  InFB v o k -> st (MV.read v o) >>= \case
    VInstance _ m -> pure $! M.findWithDefault (VBool False) k m
    _ -> pure (VBool False)

writePlace :: Shape -> Place s -> Value -> M s ()
writePlace sh pl x = case pl of
  Slot v o -> case sh of
    Leaf -> st (MV.write v o $! x)
    _ -> st (load v o sh x) >>= \ok -> if ok then pure () else abort Bail
  InFB v o k -> st $ MV.read v o >>= \case
    VInstance n m -> MV.write v o $! VInstance n (M.insert k x m)
    _ -> pure ()

------------------------------------------------------------------------------
-- Translation

data Cx = Cx
  { cPol :: Policies
  , cProg :: Program
  , cGlobals :: M.Map Text (Int, Shape)
  , cSelf :: M.Map Text (Int, Shape) -- ^ the running POU's variables
  , cThis :: Maybe Shape -- ^ the instance THIS names, as this code sees it (a function has none)
  , cChecked :: Bool -- ^ the implicit check functions apply in this code (the readable cxChecked)
  , cLoop :: Bool -- ^ inside a loop (CONTINUE is only translated there)
  , cPous :: LM.Map Text (Maybe Code) -- ^ every user POU's translated body, built when first used
  , cMethods :: LM.Map (Text, Text) (Maybe Code)
  -- ^ every method's, by the key of the type that declares it and its own
  , cRoots :: [(Root, Type, Integer, Maybe (Int, Shape))]
  -- ^ the roots of memory that stay in place (the readable evaluator's
  -- MemoryMap), each with its slots when the store holds it
  , cLayout :: Layout
  , cAddresses :: V.Vector (Maybe Integer)
  -- ^ 'slotAddress' of each slot of the store, computed when first asked
  -- and then remembered for the run
  }

-- | The place a path of steps from a variable's start reaches in its
-- slots, and its shape there.
descend :: Shape -> [Step] -> Maybe (Int, Shape)
descend sh = \case
  [] -> Just (0, sh)
  StepField k : rest | Record _ fs _ <- sh -> do
    (o, s) <- M.lookup k fs
    (o', s') <- descend s rest
    Just (o + o', s')
  StepIndex is : rest
    | Array bs e esz _ <- sh
    , length is == length bs
    , and [i >= lo && i <= hi | ((lo, hi), i) <- zip bs is] -> do
        let linear = foldl (\acc ((lo, hi), i) -> acc * (hi - lo + 1) + (i - lo)) 0 (zip bs is)
        (o', s') <- descend e rest
        Just (fromInteger linear * esz + o', s')
  _ -> Nothing

-- | The path from a variable's start to its slot o: to the elementary
-- value or standard FB instance there, which starts where every structure
-- and array around it that starts at o starts.
stepsTo :: Shape -> Int -> Maybe [Step]
stepsTo sh o = case sh of
  Record _ fs _ -> listToMaybe [StepField k : rest | (k, (fo, s)) <- M.toList fs, o >= fo, o < fo + size s, Just rest <- [stepsTo s (o - fo)]]
  Array bs e esz n
    | esz > 0 && o >= 0 && o < esz * n ->
        let (i, r) = o `divMod` esz
         in (StepIndex (unlinear bs (toInteger i)) :) <$> stepsTo e r
  _ | o == 0 -> Just []
  _ -> Nothing
  where
    -- TC-TYPE-43: the rightmost index varies fastest
    unlinear bs i = snd (foldr (\(lo, hi) (rest, acc) -> let n = hi - lo + 1 in (rest `div` n, lo + rest `mod` n : acc)) (i, []) bs)

-- | ADR of the store's slot o (NX-TYPE-75): the readable @addressOf@ of its
-- path; Nothing outside the roots the store holds.
slotAddress :: Cx -> Int -> Maybe Integer
slotAddress cx o = do
  (_, t, base, Just (start, sh)) <- find (\(_, _, _, slots) -> maybe False (\(start, sh) -> o >= start && o < start + size sh) slots) (cRoots cx)
  steps <- stepsTo sh (o - start)
  (off, _) <- offsetOf (cLayout cx) t steps
  Just (base + off)

-- | The store's slot of the variable of a type at an address (NX-TYPE-75),
-- found as the readable @variableAt@ finds it, and the type of the
-- variable there; Nothing where the store holds no such variable.
slotAt :: Cx -> Integer -> Type -> Maybe (Int, Type)
slotAt cx a t = do
  let ly = cLayout cx
  -- a direct-address area or a call's frame: not the store's
  Nothing <- Just (areaAt a)
  (_, rt, base, slots) <- find (\(_, rt, base, _) -> a >= base && a < base + max 1 (sizeInBytes ly rt)) (cRoots cx)
  (start, sh) <- slots
  steps <- locate ly rt (a - base) t
  (o, _) <- descend sh steps
  (_, found) <- offsetOf ly rt steps
  -- a pointer to an FB reaches any FB there: the slots are read on the
  -- pointer type's layout only when the instance is of that type or
  -- derived from it
  case (found, t) of
    (TFB n, TFB m) | not (derivedFrom (cProg cx) n m) -> Nothing
    -- an FB's type by its key, which a virtual call dispatches on
    (TFB n, _) -> Just (start + o, TFB (key n))
    _ -> Just (start + o, found)

-- | 'slotAt' for one type, remembered for the addresses of the store's
-- slots (where every variable starts): a pointer's target is found again at
-- each @^@.
slotAtOf :: Cx -> Type -> Int -> Maybe (Int, Type)
slotAtOf cx t
  -- the store's addresses close together (as they are): a table by address
  | not (null addresses), hi - lo < 1048576 =
      let !table = V.accum (\_ x -> Just x) (V.replicate (hi - lo + 1) Nothing) [(a - lo, slotAt cx (toInteger a) t) | a <- addresses]
       in \a -> case if lo <= a && a <= hi then V.unsafeIndex table (a - lo) else Nothing of
            Just known -> known
            Nothing -> slotAt cx (toInteger a) t
  | otherwise = \a -> fromMaybe (slotAt cx (toInteger a) t) (IM.lookup a known)
  where
    addresses = [fromInteger a | Just a <- V.toList (cAddresses cx), a >= 0, a <= toInteger (maxBound :: Int)] :: [Int]
    lo = minimum addresses
    hi = maximum addresses
    known = IM.fromList [(a, slotAt cx (toInteger a) t) | a <- addresses]

-- | A function block type is the other or derived from it (NX-POU-43).
derivedFrom :: Program -> Text -> Text -> Bool
derivedFrom prog n m = go (16 :: Int) (key n)
  where
    go 0 _ = False
    go i k = k == key m || maybe False (go (i - 1)) (lookupPou prog k >>= pdBase)

-- | A POU's body: VAR_TEMP reset (TC-VAR-8), then its statements.
data Code = Code Shape Body'

newtype Body' = Body' (forall s. M s Flow)

data Ex = Ex !(forall s. M s Value)

data St = St !(forall s. M s Flow)

-- | What an FB call runs on the instance at these slots, of this type.
data Callee = Callee !(forall s. MV.MVector s Value -> Int -> Text -> M s ())

-- | An instance a call runs on, found when the call runs: its slots, where
-- it starts in them and its type's key (the dynamic type: a virtual call
-- dispatches on it).
data Recv = Recv !(forall s. M s (Found s))

data Found s = Found !(MV.MVector s Value) !Int !Text

-- | A method as one type runs it: on the instance, with the inputs' values.
data Invoke = Invoke !(forall s. MV.MVector s Value -> Int -> Text -> Args -> M s Value)

-- | The inputs' values of a call, in order.
data Args = NoArgs | Arg !Value !Args

-- | A call's inputs, evaluated in order.
data EvalArgs = EvalArgs !(forall s. M s Args)

evalArgs :: [Ex] -> EvalArgs
evalArgs = foldr (\(Ex v) (EvalArgs more) -> EvalArgs (M (\e -> unM v e >>= \x -> unM more e >>= \xs -> pure $! Arg x xs))) (EvalArgs (pure NoArgs))

-- | The inputs stored into an instance or a frame (its slots, where it
-- starts), in order.
data Stores = Stores !(forall s. MV.MVector s Value -> Int -> Args -> M s ())

-- | A store of one input.
data Put = Put !(forall s. MV.MVector s Value -> Int -> Value -> M s ())

-- | A call of a POU on a frame of its own (a function, a method): the
-- inputs' values in, the result out; the environment's change for the body
-- (THIS of a method).
data Framed = Framed !(forall s. (Env s -> Env s) -> Args -> M s Value)

-- | How a statement ended: on to the next, or EXIT, RETURN, CONTINUE, a
-- JMP to a label (upper case).
data Flow = Next | Exited | Returned | Continued | Jumped !Text

-- | The readable evaluator's @runCycle@ for programs of the slice.
fastCycle :: Policies -> Program -> Maybe (Integer -> Machine -> (Machine, Maybe Stop))
fastCycle pol prog = do
  fast <- fastCycleOnly pol prog
  pure $ \clock m0 -> fromMaybe (runCycle pol prog clock m0) (fast clock m0)

-- | The fast cycle alone: Nothing for a cycle it leaves to the readable
-- evaluator (a machine of an unexpected shape, a pointer it does not
-- follow), so that the tests can tell which cycles it ran.
fastCycleOnly :: Policies -> Program -> Maybe (Integer -> Machine -> Maybe (Machine, Maybe Stop))
fastCycleOnly pol prog = do
  cycles <- fastCycles pol prog
  pure $ \clock m0 -> (\(m, _, stop) -> (m, stop)) <$> cycles [clock] m0

-- | Consecutive cycles at these clocks, on the same slots: the machine is
-- loaded before the first and rebuilt after the last, which is the one
-- that stopped if one did; with the number of cycles run. The same as
-- 'runCycle' cycle after cycle (nothing is written between them). Nothing
-- when a cycle leaves the slice: the caller then runs them one by one.
fastCycles :: Policies -> Program -> Maybe ([Integer] -> Machine -> Maybe (Machine, Int, Maybe Stop))
fastCycles pol prog = do
  -- outside the slice: VAR_CONFIG, periodic tasks (runCycle's schedule)
  when (not (null (prVarConfig prog)) || not (M.null (prPeriods prog))) Nothing
  -- outside the slice: an overflow flag (MT-OP-7), which runCycle's operators set
  when (pOverflowFlag pol /= NoOverflowFlag) Nothing
  gshapes <- forM [v | v <- prGlobals prog, viAt v == Nothing] $ \v -> (viKey v,) <$> shapeOf prog (viType v)
  let instances = [(key i, d) | (i, t) <- prInstances prog, Just d <- [lookupPou prog t]]
      distinct = M.toList (M.fromList instances)
  pshapes <- forM distinct $ \(k, d) -> (k,) <$> pouShape prog d
  let place base xs = zip (map fst xs) (zip (scanl (+) base (map (size . snd) xs)) (map snd xs))
      globals = place 0 gshapes
      progs = place (sum (map (size . snd) gshapes)) pshapes
      total = sum (map (size . snd) (gshapes ++ pshapes))
      memory = memoryMap prog
      stored r = case r of
        RootGlobal k -> lookup k globals
        RootProgram k -> lookup k progs
        _ -> Nothing
      cx = Cx pol prog (M.fromList globals) M.empty Nothing False False pous methods [(r, t, a, stored r) | (r, t, a) <- mmRoots memory] (mmLayout memory) addresses
      addresses = V.generate total (slotAddress cx)
      pous = LM.fromList [(k, translatePou cx d) | (k, d) <- M.toList (prPous prog), Statements _ <- [pdBody d]]
      -- a method is translated on the variables of the type that declares it
      methods = LM.fromList [((k, mk), translateMethod cx d md) | (k, d) <- M.toList (prPous prog), (mk, md) <- M.toList (pdMethods d)]
  runs <- forM instances $ \(k, d) -> do
    Code _ (Body' body) <- join (LM.lookup (key (pdName d)) pous)
    (base, _) <- lookup k progs
    Just (Body' (within (\e -> e {eSelf = eStore e, eBase = base, eThis = eStore e, eThisBase = base, eThisType = key (pdName d)}) body))
  let cyclesWith clocks m0 = runST $ do
        store <- MV.new total
        ok <- foldlM (\ok (k, (o, s)) -> if ok then maybe (pure False) (load store o s) (M.lookup k (mGlobals m0)) else pure False) True globals
        ok' <- foldlM (\ok (k, (o, s)) -> if ok then maybe (pure False) (load store o s) (M.lookup k (mPrograms m0)) else pure False) ok progs
        if not ok'
          then pure Nothing
          else do
            steps <- MU.replicate 1 0
            frames <- newSTRef []
            -- each cycle as runCycle starts it: no steps, no frames
            let go ran clock = \case
                  [] -> pure (Right (ran, clock, Nothing))
                  c : later -> do
                    MU.write steps 0 0
                    writeSTRef frames []
                    r <- attempt (mapM_ (\(Body' b) -> b) runs) (Env store store 0 store 0 "" 0 steps frames c)
                    case r of
                      Left Bail -> pure (Left ())
                      Left (Faulted p f) -> pure (Right (ran + 1, c, Just (StopFault p f)))
                      Right () -> go (ran + 1) c later
            outcome <- go 0 (mClock m0) clocks
            case outcome of
              Left () -> pure Nothing
              Right (ran, clock, stop) -> do
                let restore pairs src = foldlM (\m (k, (o, s)) -> maybe (pure m) (\old -> (\v -> M.insert k v m) <$> rebuild store o s old) (M.lookup k m)) src pairs
                gs <- restore globals (mGlobals m0)
                ps <- restore progs (mPrograms m0)
                n <- MU.read steps 0
                -- the frames of the calls a runtime error interrupted
                open <- case stop of
                  Nothing -> pure []
                  Just _ -> readSTRef frames >>= mapM (\(d, s, initial, v) -> (d,) <$> rebuild v 0 s initial)
                pure (Just (m0 {mGlobals = gs, mPrograms = ps, mClock = clock, mSteps = n, mFrames = M.fromList open}, ran, stop))
  -- a traced run is the readable evaluator's
  pure $ \clocks m0 -> case mTrace m0 of
    Nothing -> cyclesWith clocks m0
    Just _ -> Nothing

translatePou :: Cx -> PouDef -> Maybe Code
translatePou cx d = do
  sh <- pouShape (cProg cx) d
  -- THIS: an FB's or a program's own instance; a function has none
  translateOn cx (if pdKind d == KFunction then Nothing else Just sh) d

-- | A method of the type d declares (NX-POU-27), on d's variables: an
-- instance of a derived type has them at the same offsets.
translateMethod :: Cx -> PouDef -> PouDef -> Maybe Code
translateMethod cx d md = do
  when (pdKind md /= KMethod) Nothing
  this <- pouShape (cProg cx) d
  translateOn cx (Just this) md

translateOn :: Cx -> Maybe Shape -> PouDef -> Maybe Code
translateOn cx this d = do
  sh <- pouShape (cProg cx) d
  fields <- case sh of
    Record _ fs _ -> Just fs
    _ -> Nothing
  ss <- case pdBody d of
    Statements ss -> Just ss
    Native _ -> Nothing
  let cx' = cx {cSelf = fields, cThis = this, cChecked = pdChecked d, cLoop = False}
  St body <- block cx' ss
  temps <- forM [v | v <- pdVars d, viSection v == SecTemp] $ \v -> (\(o, s) -> (o, s, viInit v)) <$> M.lookup (viKey v) fields
  pure $ Code sh $ Body' $ do
    e <- env
    forM_ temps $ \(o, s, x) -> writePlace s (Slot (eSelf e) (eBase e + o)) x
    body

-- | A block: its statements in turn, until one ends it; a JMP to one of
-- its labels (from it or from a block inside it) goes on from that label
-- (NX-STMT-42), as the readable @execBlock@.
block :: Cx -> [CStmt] -> Maybe St
block cx ss = do
  sts <- mapM (stmt cx) ss
  let -- the statements chained once, here, rather than walked at each run
      go = foldr andThen (St (pure Next))
      andThen (St s) (St rest) = St (M (\e -> unM s e >>= \case
        Next -> unM rest e
        fl -> pure fl))
      -- each label's first place, the rest of the block from it
      labels = M.fromListWith (\_ first -> first) [(l, go (drop i sts)) | (i, CLabel _ l) <- zip [0 ..] ss]
      run (St xs) = xs >>= \case
        Jumped l | Just rest <- M.lookup l labels -> run rest
        fl -> pure fl
  Just $ case (M.null labels, sts) of
    (True, [one]) -> one
    (True, _) -> go sts
    _ -> St (run (go sts))

-- | A loop's body: Nothing when EXIT left the loop (TC-STMT-36, TC-STMT-37).
loopBody :: St -> M s (Maybe Flow)
loopBody (St s) = s >>= \case
  Exited -> pure Nothing
  Continued -> pure (Just Next)
  fl -> pure (Just fl)

stmt :: Cx -> CStmt -> Maybe St
stmt cx = \case
  CAssign p r t e
    -- a small value into an elementary variable: the value the store
    -- keeps as it is ('storeOn') is written without a check
    | Just vs <- small (ceType e)
    , Just keeps <- keptAsIs t vs
    , Just (Leaf, w) <- whereIs cx p r
    , Just (Fitter fitted) <- fitter cx p t
    , Just (IEx i) <- intExpr cx vs e -> do
        -- (on the environment: a closure built at each store would cost more
        -- than the store)
        let store b o n e = unM (if keeps n then writeAt b o (boxed vs n) else fitted (boxed vs n) >>= writeAt b o) e
        case w of
          Fixed b o -> Just $ St $ M $ \e -> do
            unM (tk p) e
            n <- unM i e
            Next <$ store b o n e
          Computed b c (Offset off) -> Just $ St $ M $ \e -> do
            unM (tk p) e
            n <- unM i e
            o <- (c +) <$> unM off e
            Next <$ store b o n e
          Anywhere _ -> assign
    | otherwise -> assign
    where
     assign = do
      -- TC-STMT-7: the value, then the target
      Ex v <- expr cx e
      (sh, w) <- whereIs cx p r
      writable sh t (ceType e)
      Fitter fitted <- fitter cx p t
      Just $ St $ case (sh, w) of
        -- an elementary value at an offset known or computed: no Place built
        (Leaf, Fixed b o) -> do
          tk p
          x <- v
          x' <- fitted x
          Next <$ writeAt b o x'
        (Leaf, Computed b c (Offset off)) -> do
          tk p
          x <- v
          o <- (c +) <$> off
          x' <- fitted x
          Next <$ writeAt b o x'
        _ | Ref target <- placeOf w -> do
          tk p
          x <- v
          pl <- target
          x' <- fitted x
          Next <$ writePlace sh pl x'
  CCallFB p c -> do
    St call <- callFB cx p c
    Just (St (tk p >> call))
  CEval p e -> do
    Ex v <- expr cx e
    Just (St (tk p >> Next <$ v))
  CIf p arms els -> do
    -- TC-STMT-9
    arms' <- forM arms $ \(c, b) -> (,) <$> condition cx c <*> block cx b
    St els' <- block cx els
    let go [] = els'
        go ((Cond c, St b) : rest) = c >>= \x -> if x then b else go rest
    Just (St (tk p >> go arms'))
  CCase p sel arms els -> do
    -- TC-STMT-11..13: the first group whose labels hold the value
    Ex s <- expr cx sel
    arms' <- forM arms $ \(ranges, b) -> (ranges,) <$> block cx b
    St els' <- block cx els
    Just $ St $ do
      tk p
      o <- ordinal (ceType sel) <$> s
      case find (\(ranges, _) -> any (\(lo, hi) -> o >= lo && o <= hi) ranges) arms' of
        Just (_, St b) -> b
        Nothing -> els'
  CFor p r t start end step body -> forLoop cx p r t start end step body
  CWhile p c body -> do
    -- TC-STMT-32
    Cond cond <- condition cx c
    b <- block cx {cLoop = True} body
    Just $ St $ M $ \e ->
      let run m = unM m e
          loop = do
            run (tk p)
            x <- run cond
            if x
              then run (loopBody b) >>= maybe (pure Next) (\case Next -> loop; fl -> pure fl)
              else pure Next
       in loop
  CRepeat p body c -> do
    -- TC-STMT-33: at least once, until the condition holds
    Cond cond <- condition cx c
    b <- block cx {cLoop = True} body
    Just $ St $ M $ \e ->
      let run m = unM m e
          loop =
            run (loopBody b) >>= \case
              Just Next -> do
                run (tk p)
                x <- run cond
                if x then pure Next else loop
              Just fl -> pure fl
              Nothing -> pure Next
       in loop
  CExit p -> Just (St (Exited <$ tk p))
  CReturn p -> Just (St (Returned <$ tk p))
  CContinue p | cLoop cx -> Just (St (Continued <$ tk p)) -- NX-STMT-35
  CJump p l -> Just (St (Jumped l <$ tk p)) -- NX-STMT-42
  CLabel _ _ -> Just (St (pure Next))
  _ -> Nothing
  where
    pol = cPol cx
    !budget = pStepBudget pol
    tk q = tick pol budget q

-- | For a small value into a target of this type, which values 'storeOn'
-- keeps as they are: an integer within an integer type's range, anything
-- in another elementary type; Nothing where the store may check.
keptAsIs :: Type -> Small -> Maybe (Int -> Bool)
keptAsIs t vs = case (t, vs) of
  (TElem e, SmallInt _ _)
    | isInt e, intBits e <= 32 ->
        let (lo, hi) = intRange e
            !lo' = fromInteger lo :: Int
            !hi' = fromInteger hi :: Int
         in Just (\n -> lo' <= n && n <= hi')
  (TElem e, _) | not (isInt e) -> Just (const True)
  _ -> Nothing

-- | A store into a target of a declared type, as the readable @fitValue@:
-- a subrange's value goes through CheckRangeSigned or CheckRangeUnsigned
-- first where one applies (NX-ERR-15, NX-ERR-16), then 'fitWhy'.
fitter :: Cx -> Pos -> Type -> Maybe Fitter
fitter cx p t = case t of
  TSubrange e lo hi -> do
    check <- implicit cx p (if isSignedInt e then "CHECKRANGESIGNED" else "CHECKRANGEUNSIGNED")
    Just $ Fitter $ \v0 -> do
      v <- case (check, v0) of
        (Just (Checker call), VInt e' n0) -> VInt e' . intValue <$> call [VInt DINT n0, VInt DINT lo, VInt DINT hi]
        _ -> pure v0
      fit store p v
  _ -> Just $ case store of
    -- (a function of every argument: 'pure' itself would be called as a
    -- closure that builds one)
    KeepsAll -> Fitter (\v -> M (\_ -> pure v))
    _ -> Fitter (fit store p)
  where
    !store = storeOn (cPol cx) t

-- | An implicit check function (NX-ERR-1..20) as the readable
-- @implicitCheck@ calls it: when the program declares it and this code is
-- checked, a call with the values converted to its inputs' types (Just
-- Nothing: no check here). Nothing outside the slice: a check function
-- that is itself checked, or has a subrange input (translating its call
-- could come back to it).
implicit :: Cx -> Pos -> Text -> Maybe (Maybe Checker)
implicit cx p name
  | cChecked cx && name `elem` prChecks (cProg cx) = case lookupPou (cProg cx) name of
      Nothing -> Just Nothing
      Just d -> do
        let params = [v | v <- pdVars d, viSection v == SecInput]
        when (pdChecked d || any (isSubrange . viType) params) Nothing
        Code sh body <- join (LM.lookup (key (pdName d)) (cPous cx))
        Framed run <- framed cx p d sh body [(viKey v, viType v) | v <- params] []
        Just $ Just $ Checker $ \args -> do
          vs <- forM (zip params args) $ \(v, a) -> orFault p (convertValue (cPol cx) (viType v) a)
          run id (foldr Arg NoArgs vs)
  | otherwise = Just Nothing
  where
    isSubrange = \case
      TSubrange {} -> True
      _ -> False

-- | A value of this type can be stored whole at a place of this shape: an
-- elementary one, or data of the very type (the readable evaluator would
-- store another array's bounds with its elements).
writable :: Shape -> Type -> Type -> Maybe ()
writable sh t from = case sh of
  Leaf -> Just ()
  _ | isData sh && t == from -> Just ()
  _ -> Nothing

-- | FOR (TC-STMT-18..31), as the readable @forLoop@: the same functions
-- decide the step, the test and the increment.
forLoop :: Cx -> Pos -> CRef -> Type -> CExpr -> CExpr -> Maybe CExpr -> [CStmt] -> Maybe St
forLoop cx p r t start end step body = do
  Ex s0 <- expr cx start
  Ex e0 <- expr cx end
  Ex stepOf <- maybe (Just (Ex (pure (forDefaultStep t)))) (expr cx) step
  (sh, Ref target) <- ref cx p r
  when (not (isLeaf sh)) Nothing
  b <- block cx {cLoop = True} body
  Fitter fitted <- fitter cx p t
  let pol = cPol cx
      !once = pForBounds pol == ForOnce
      !budget = pStepBudget pol
      current v ex = if once then pure v else ex
      -- the increment (readable forIncrement, binary +, fitValue)
      increment pl i' stNow = do
        let (elemT, _, ends) = forIncrement pol t i' stNow
        if ends
          then pure False
          else do
            v <- orFault p (binary pol BAdd i' (VInt elemT stNow))
            True <$ (fitted v >>= writePlace Leaf pl)
      -- a small control variable, final value and step, on Int
      typed = do
        TElem !te <- Just t
        ctl@(SmallInt _ _) <- small t
        endS <- small (ceType end)
        IEx endI <- intExpr cx endS end
        IEx stepI <- case step of
          Nothing -> (\n -> IEx (pure n)) <$> (case forDefaultStep t of VInt _ (IS n) -> Just (I# n); _ -> Nothing)
          Just se -> small (ceType se) >>= \sm -> intExpr cx sm se
        let (lo, hi) = rangeUnder pol te
            !lo' = fromInteger lo :: Int
            !hi' = fromInteger hi :: Int
            !tag = fromEnum te
        Just $ St $ do
          x0 <- s0
          pl <- target
          fitted x0 >>= writePlace Leaf pl
          e0' <- endI
          st0 <- stepI
          case pl of
            -- the control variable's slot, read and written in place
            -- (a loop in ST on this environment: a known function that
            -- calls itself, not a closure entered again at each round)
            Slot vec o -> M $ \en ->
              let run m = unM m en
                  loop = do
                    run (tick pol budget p)
                    e <- run (current e0' endI)
                    stp <- run (current st0 stepI)
                    i <- MV.read vec o >>= run . unboxed ctl
                    -- TC-STMT-21, TC-STMT-23
                    if not (if stp >= 0 then i <= e else i >= e)
                      then pure Next
                      else
                        run (loopBody b) >>= \case
                          Just Next -> do
                            i' <- MV.read vec o
                            stNow <- run (current st0 stepI)
                            case i' of
                              -- within the type: the sum, as binary + gives it
                              VInt e' (IS x)
                                | fromEnum e' == tag
                                , let n = I# x + stNow
                                , lo' <= n && n <= hi' -> (MV.write vec o $! VInt te (toInteger n)) >> loop
                              _ -> run (increment pl i' (toInteger stNow)) >>= \case
                                True -> loop
                                False -> pure Next
                          Just fl -> pure fl
                          Nothing -> pure Next
               in loop
            InFB {} -> abort Bail
  Just $ flip fromMaybe typed $ St $ do
    x0 <- s0
    pl <- target
    fitted x0 >>= writePlace Leaf pl
    e0' <- e0
    st0 <- stepOf
    let loop = do
          tick pol (pStepBudget pol) p
          e <- current e0' e0
          stp <- current st0 stepOf
          i <- readPlace Leaf pl
          if not (forGoesOn (intOf i) (intOf e) (intOf stp))
            then pure Next
            else
              loopBody b >>= \case
                Just Next -> do
                  i' <- readPlace Leaf pl
                  stNow <- current st0 stepOf
                  increment pl i' (intOf stNow) >>= \case
                    True -> loop
                    False -> pure Next
                Just fl -> pure fl
                Nothing -> pure Next
    loop
  where
    intOf = \case
      VInt _ n -> n
      _ -> 0

-- | An FB call (TC-POU-33..36), as the readable @callFB@: the inputs
-- evaluated, the instance found, the inputs stored, the body run on the
-- instance, the @=>@ outputs copied.
callFB :: Cx -> Pos -> FBCall -> Maybe St
callFB cx p c = do
  d <- lookupPou (cProg cx) (fcType c)
  when (not (null (fcInOuts c))) Nothing
  (sh, Recv inst) <- receiver cx p (fcInstance c)
  EvalArgs args <- evalArgs <$> mapM (expr cx . snd) (fcInputs c)
  Stores puts <- inputStores cx p d sh [(k, ceType e) | (k, e) <- fcInputs c]
  outs <- forM (fcOutputs c) $ \(k, r, t) -> do
    (o, s) <- member sh k
    (ts, Ref target) <- ref cx p r
    when (not (isLeaf ts && isLeaf s)) Nothing
    f <- fitter cx p t
    Just (o, Ref target, f)
  -- a native FB's VAR_TEMP (none of the standard ones has any)
  let temps = M.fromList [(viKey v, viInit v) | v <- pdVars d, viSection v == SecTemp]
  Callee run <- case (sh, pdBody d) of
    -- the twin of the standard FB's meaning, on its slots
    (Record _ fs _, Native _) -> do
      when (not (M.null temps)) Nothing
      Twin f <- twin pol (pdName d) (\k -> fst <$> M.lookup k fs)
      -- (the clock taken here, not selected from the environment by a thunk)
      Just $ Callee $ \vec base _ -> M (\e -> let !clock = eClock e in saturated (f clock vec base))
    -- the standard FB's meaning on the instance's variables
    (Opaque, Native f) -> Just $ Callee $ \vec o _ -> do
      clock <- eClock <$> env
      st $ MV.read vec o >>= \case
        VInstance n vars -> MV.write vec o $! VInstance n (f pol clock (M.union temps vars))
        _ -> pure ()
    (Record {}, Statements _) -> do
      Code _ (Body' body) <- join (LM.lookup (key (pdName d)) (cPous cx))
      Just (Callee (\vec base t -> () <$ within (\e -> e {eSelf = vec, eBase = base, eThis = vec, eThisBase = base, eThisType = t, eDepth = eDepth e + 1}) body))
    _ -> Nothing
  Just $ St $ do
    xs <- args
    Found vec base dyn <- inst
    puts vec base xs
    deeper pol p
    run vec base dyn
    forM_ outs $ \(o, Ref target, Fitter f) -> do
      v <- readPlace Leaf (at (Slot vec base) o)
      tpl <- target
      f v >>= writePlace Leaf tpl
    pure Next
  where
    pol = cPol cx

paramType :: PouDef -> Text -> Type
paramType d k = maybe (TElem BOOL) viType (varByKey d k)

-- | The stores of a call's inputs (by key, with their values' types) into
-- the POU's instance or frame of this shape: each value fitted to the
-- input's type.
inputStores :: Cx -> Pos -> PouDef -> Shape -> [(Text, Type)] -> Maybe Stores
inputStores cx p d sh = foldr input (Just (Stores (\_ _ _ -> pure ())))
  where
    input (k, from) rest = do
      Stores more <- rest
      (o, s) <- member sh k
      writable s (paramType d k) from
      Fitter f <- fitter cx p (paramType d k)
      -- (each closure takes the environment itself, so that GHC makes one
      -- function of it and builds nothing at each call)
      let !(Put put) = case (o, s) of
            (Right i, Leaf) -> Put (\vec base x -> M (\e -> unM (f x) e >>= \y -> MV.write vec (base + i) $! y))
            _ -> Put (\vec base x -> M (\e -> unM (f x >>= writePlace s (at (Slot vec base) o)) e))
      Just $ Stores $ \vec base xs -> M $ \e -> case xs of
        Arg x later -> unM (put vec base x) e >> unM (more vec base later) e
        NoArgs -> pure ()

-- | A variable of an instance: at an offset of its record, or (0) in a
-- standard FB's map.
member :: Shape -> Text -> Maybe (Either Text Int, Shape)
member sh k = case sh of
  Record _ fs _ -> (\(o, s) -> (Right o, s)) <$> M.lookup k fs
  Opaque -> Just (Left k, Leaf)
  _ -> Nothing

at :: Place s -> Either Text Int -> Place s
at pl m = case (pl, m) of
  (Slot v o, Right o') -> Slot v (o + o')
  (Slot v o, Left k) -> InFB v o k
  (InFB v o k, _) -> InFB v o k

-- | A function call (TC-POU-5, TC-POU-6), as the readable @callFunction@:
-- the inputs evaluated, then the call on a frame of its own.
callFunction :: Cx -> Pos -> Text -> [(Text, CExpr)] -> [(Text, CRef, Type)] -> Maybe Ex
callFunction cx p f ins outs = do
  d <- lookupPou (cProg cx) f
  when (pdKind d /= KFunction) Nothing
  Code sh (Body' body) <- join (LM.lookup (key (pdName d)) (cPous cx))
  EvalArgs args <- evalArgs <$> mapM (expr cx . snd) ins
  Framed run <- framed cx p d sh (Body' body) (map (\(k, e) -> (k, ceType e)) ins) outs
  Just (Ex (args >>= run id))

-- | A call on a fresh frame of initial values (which a runtime error inside
-- leaves in the machine's frames), as the readable @callFunctionWith@: the
-- inputs stored, the body, the @=>@ outputs copied, the result read.
framed :: Cx -> Pos -> PouDef -> Shape -> Body' -> [(Text, Type)] -> [(Text, CRef, Type)] -> Maybe Framed
framed cx p d sh (Body' body) ins outs = do
  let initial = VInstance (pdName d) (M.fromList [(viKey v, viInit v) | v <- pdVars d])
  Stores stores <- inputStores cx p d sh ins
  outs' <- forM outs $ \(k, r, t) -> do
    (o, s) <- member sh k
    (ts, Ref target) <- ref cx p r
    when (not (isLeaf ts && isLeaf s)) Nothing
    f <- fitter cx p t
    Just (o, Ref target, f)
  (result, rs) <- member sh (key (pdName d))
  when (not (isLeaf rs)) Nothing
  -- the initial frame laid out once; each call starts from a copy
  slots <- runST $ do
    v <- MV.new (size sh)
    ok <- load v 0 sh initial
    if ok then Just <$> V.freeze v else pure Nothing
  Just $ Framed $ \this xs -> do
    deeper (cPol cx) p
    e <- env
    let !depth = eDepth e + 1
    vec <- st (V.thaw slots)
    st (modifySTRef' (eFrames e) ((depth, sh, initial, vec) :))
    let frame = Slot vec 0
    stores vec 0 xs
    _ <- within (\e' -> this e' {eSelf = vec, eBase = 0, eDepth = depth}) body
    forM_ outs' $ \(o, Ref target, Fitter f) -> do
      v <- readPlace Leaf (at frame o)
      tpl <- target
      f v >>= writePlace Leaf tpl
    x <- readPlace Leaf (at frame result)
    st (modifySTRef' (eFrames e) (drop 1))
    pure x

-- | A method call (NX-POU-30), as the readable @callMethod@: the instance
-- found, the method its type has or inherits (NX-POU-31; SUPER^'s: the
-- named type's, NX-POU-46), the inputs evaluated, then the call on a frame
-- of the method's with THIS the instance.
callMethod :: Cx -> Pos -> Dispatch -> CRef -> [(Text, CExpr)] -> [(Text, CRef, Type)] -> Maybe Ex
callMethod cx p d r ins outs = do
  (sh, Recv recv) <- receiver cx p r
  EvalArgs args <- evalArgs <$> mapM (expr cx . snd) ins
  let m = case d of
        Virtual k -> k
        Static _ k -> k
      -- each type's method, built when a call first reaches that type: the
      -- receiver's type and those derived from it (NX-POU-43), or SUPER^'s
      byType = LM.fromList [(k, invoke k) | k <- M.keys (prPous (cProg cx)), reaches k]
      reaches k = case d of
        Static t _ -> k == key t
        Virtual _ -> maybe True (derivedFrom (cProg cx) k) declared
      declared = case sh of
        Record (Just n) _ _ -> Just n
        _ -> Nothing
      invoke t = do
        md <- findMethod (cProg cx) t m
        owner <- declaring t
        Code sh body <- join (LM.lookup (owner, key m) (cMethods cx))
        Framed run <- framed cx p md sh body (map (\(k, e) -> (k, ceType e)) ins) outs
        Just (Invoke (\vec base dyn xs -> M (\e -> saturated (unM (run (\e' -> e' {eThis = vec, eThisBase = base, eThisType = dyn}) xs) e))))
      -- the type whose declaration holds the method (as findMethod walks)
      declaring = go (16 :: Int)
        where
          go 0 _ = Nothing
          go i k = do
            td <- lookupPou (cProg cx) k
            if M.member (key m) (pdMethods td) then Just (key (pdName td)) else pdBase td >>= go (i - 1)
  Just $ Ex $ do
    Found vec base dyn <- recv
    let owner = case d of
          Virtual _ -> dyn
          Static t _ -> key t
    case join (LM.lookup owner byType) of
      Nothing -> abort Bail
      Just (Invoke run) -> args >>= run vec base dyn

-- | What a pointer points at (NX-TYPE-75): the variable of the pointer's
-- base type at its address, with the type of the variable found there.
-- (CheckPointer, which is told whether the access writes, is the readable
-- evaluator's.)
pointee :: Cx -> Pos -> CExpr -> Type -> Maybe (Shape, Target)
pointee cx p e t = do
  Nothing <- implicit cx p "CHECKPOINTER"
  -- an address is a DWORD (NX-TYPE-75)
  IEx ptr <- intExpr cx (smallInt DWORD) e
  sh <- shapeOf (cProg cx) t
  let !found = slotAtOf cx t
  Just $ (sh,) $ Target $ do
    a <- ptr
    case found a of
      Just target -> pure target
      _ -> abort Bail

-- | The store's slot a pointer's target starts at, and the type there.
data Target = Target !(forall s. M s (Int, Type))

-- | The instance a call runs on, as the readable evaluator finds it (THIS,
-- a pointer's target, a variable), with its type's key; Nothing outside the
-- slice.
receiver :: Cx -> Pos -> CRef -> Maybe (Shape, Recv)
receiver cx p = \case
  CThis -> do
    sh <- cThis cx
    Just (sh, Recv (M (\e -> pure $! Found (eThis e) (eThisBase e) (eThisType e))))
  CDeref e t -> do
    (sh, Target target) <- pointee cx p e t
    Just $ (sh,) $ Recv $
      target >>= \case
        (o, TFB ty) -> M (\en -> pure $! Found (eStore en) o ty)
        _ -> abort Bail
  r -> do
    (sh, w) <- whereIs cx p r
    let !t = case sh of
          Record (Just n) _ _ -> key n
          _ -> ""
    let found vec i = pure $! Found vec i t
    Just $ (sh,) $ Recv $ case w of
      Fixed b o -> M (\e -> atBase b e o found)
      Computed b c (Offset off) -> off >>= \o -> M (\e -> atBase b e (c + o) found)
      Anywhere (Ref pl) ->
        pl >>= \case
          Slot vec i -> found vec i
          InFB {} -> abort Bail

-- | Where a reference lies, as the readable @refPath@: indices evaluated,
-- then checked in turn (policy @index-out-of-range@).
ref :: Cx -> Pos -> CRef -> Maybe (Shape, Ref)
ref cx p r = (\(sh, w) -> (sh, placeOf w)) <$> whereIs cx p r

-- | Where a reference lies, as far as the translation can tell: at an
-- offset from the start of the store's slots, of the running POU's or of
-- THIS's, fixed, or a fixed part (the fields) plus one computed when the
-- code runs (the indices, a pointer's target); or anywhere (a standard
-- FB's variable in its map). The first two are read and written without
-- building a 'Place'.
data Where = Fixed !Base !Int | Computed !Base !Int !Offset | Anywhere !Ref

data Base = InStore | InSelf | InThis

data Offset = Offset !(forall s. M s Int)

-- | The slots and the index of the slot at an offset from a base.
atBase :: Base -> Env s -> Int -> (MV.MVector s Value -> Int -> r) -> r
atBase b e o k = case b of
  InStore -> k (eStore e) o
  InSelf -> k (eSelf e) (eBase e + o)
  InThis -> k (eThis e) (eThisBase e + o)
{-# INLINE atBase #-}

slotOf :: Base -> Env s -> Int -> Place s
slotOf b e o = atBase b e o Slot

placeOf :: Where -> Ref
placeOf = \case
  Fixed b o -> Ref (M (\e -> pure $! slotOf b e o))
  Computed b c (Offset off) -> Ref (off >>= \o -> M (\e -> pure $! slotOf b e (c + o)))
  Anywhere r -> r

-- | A write of an elementary value at an offset from a base.
writeAt :: Base -> Int -> Value -> M s ()
writeAt b o x = M (\e -> atBase b e o (\vec i -> MV.write vec i $! x))
{-# INLINE writeAt #-}

-- | A read of an elementary value.
readAt :: Where -> Ex
readAt = \case
  Fixed b o -> Ex (M (\e -> atBase b e o MV.read))
  Computed b c (Offset off) -> Ex (off >>= \o -> M (\e -> atBase b e (c + o) MV.read))
  Anywhere (Ref pl) -> Ex (pl >>= readLeaf)

whereIs :: Cx -> Pos -> CRef -> Maybe (Shape, Where)
whereIs cx p = \case
  CLocal k -> do
    (o, s) <- M.lookup k (cSelf cx)
    Just (s, Fixed InSelf o)
  CGlobal k -> do
    (o, s) <- M.lookup k (cGlobals cx)
    Just (s, Fixed InStore o)
  CField r f -> do
    (sh, w) <- whereIs cx p r
    (m, s) <- member sh f
    Just $ (s,) $ case (w, m) of
      (Fixed b o, Right o') -> Fixed b (o + o')
      (Computed b c off, Right o') -> Computed b (c + o') off
      _ | Ref base <- placeOf w -> Anywhere (Ref ((`at` m) <$> base))
  CIndex r ixs -> do
    (Array bs e esz _, w) <- whereIs cx p r
    when (length ixs /= length bs) Nothing
    -- NX-ERR-5..8: CheckBounds' result is the index
    check <- implicit cx p "CHECKBOUNDS"
    let pol = cPol cx
        bounded n0 (lo, hi) = case check of
          Just (Checker call) -> intValue <$> call [VInt DINT n0, VInt DINT lo, VInt DINT hi]
          Nothing -> pure n0
    -- the offset of the element from the array's start (each index
    -- translated once: an index holds others)
    Offset element <- case (ixs, bs, check) of
      -- one small index within the bounds: no policy applies
      ([ix], [b@(lo, hi)], Nothing)
        | Just sm@(SmallInt _ _) <- small (ceType ix) -> do
            IEx i <- intExpr cx sm ix
            let !lo' = fromInteger lo :: Int
                !hi' = fromInteger hi :: Int
            Just $ Offset $ i >>= \x ->
              if lo' <= x && x <= hi'
                then pure $! (x - lo') * esz
                else (\n' -> fromInteger (n' - lo) * esz) <$> orFault p (fst (indexWhy pol b (toInteger x)))
      _ -> do
        is <- mapM (expr cx) ixs
        Just $ case (is, bs, check) of
          -- one index within the bounds: no policy applies
          ([Ex i], [b@(lo, hi)], Nothing) ->
            let !lo' = fromInteger lo :: Int
                !hi' = fromInteger hi :: Int
             in Offset $ i >>= \case
                  VInt _ (IS x) | lo' <= I# x && I# x <= hi' -> pure $! (I# x - lo') * esz
                  VInt _ n -> (\n' -> fromInteger (n' - lo) * esz) <$> orFault p (fst (indexWhy pol b n))
                  _ -> abort Bail
          _ -> Offset $ do
            vs <- mapM (\(Ex i) -> i) is
            ns <- forM vs $ \case
              VInt _ n -> pure n
              _ -> abort Bail
            checked <- forM (zip ns bs) $ \(n0, b) -> bounded n0 b >>= \n -> orFault p (fst (indexWhy pol b n))
            -- TC-TYPE-43: the rightmost index varies fastest
            pure $! fromInteger (foldl (\acc ((lo, hi), x) -> acc * (hi - lo + 1) + (x - lo)) 0 (zip bs checked)) * esz
    -- the array's place first, then the indices
    Just $ (e,) $ case w of
      Fixed b o -> Computed b o (Offset element)
      Computed b c (Offset off) -> Computed b c (Offset (off >>= \o -> (o +) <$> element))
      Anywhere (Ref base) -> Anywhere $ Ref $ do
        pl <- base
        o' <- element
        case pl of
          Slot v o -> pure $! Slot v (o + o')
          InFB {} -> abort Bail
  -- NX-POU-28: THIS^, the instance the code runs on
  CThis -> do
    sh <- cThis cx
    Just (sh, Fixed InThis 0)
  -- NX-POU-27: a variable of the instance, inside one of its methods
  CInstance k -> do
    Record _ fs _ <- cThis cx
    (o, s) <- M.lookup k fs
    Just (s, Fixed InThis o)
  CDeref e t -> do
    (sh, Target target) <- pointee cx p e t
    Just (sh, Computed InStore 0 (Offset (fst <$> target)))
  _ -> Nothing

-- | An expression, as the readable @eval@, through the same meaning
-- functions: an operator or a conversion whose result is a small value
-- computes on 'Int' ('small'), the rest on values.
expr :: Cx -> CExpr -> Maybe Ex
expr cx ce = case (ceNode ce, small (ceType ce)) of
  (CBinary {}, Just sm) -> onInt sm
  (CUnary {}, Just sm) -> onInt sm
  (CConvert {}, Just sm) -> onInt sm
  _ -> exprValue cx ce
  where
    onInt sm = do
      IEx i <- intExpr cx sm ce
      Just (Ex (boxed sm <$> i))

-- | An expression computed on values.
exprValue :: Cx -> CExpr -> Maybe Ex
exprValue cx ce = case ceNode ce of
  CConst v -> Just (Ex (pure v))
  CRead r -> do
    (sh, w) <- whereIs cx pos r
    case sh of
      Leaf -> Just (readAt w)
      _ | isData sh, Ref pl <- placeOf w -> Just (Ex (pl >>= readPlace sh))
      _ -> Nothing
  CUnary o a -> do
    Ex x <- expr cx a
    Just (Ex (x >>= orFault pos . unary pol o))
  CBinary o a b -> do
    Ex x <- expr cx a
    Ex y0 <- expr cx b
    -- NX-ERR-11..13: CheckDiv*'s result is the divisor
    let !(Binary operator) = binaryOn pol o (ceType a) (ceType b)
    check <- case (o, baseElem (ceType b) >>= checkDivName) of
      (BDiv, Just name) -> implicit cx pos name
      _ -> Just Nothing
    let y = case check of
          Just (Checker call) -> y0 >>= \v -> call [v] >>= orFault pos . convertValue pol (ceType b)
          Nothing -> y0
    -- TC-OP-6: short-circuit is a policy; TC-OP-5: the left operand first
    Just $ Ex $ do
      u <- x
      case (o, u, pShortCircuit pol) of
        (BAnd, VBool False, ShortCircuit) -> pure u
        (BOr, VBool True, ShortCircuit) -> pure u
        _ -> y >>= \v -> orFault pos (operator u v)
  -- NX-CONV-35: TRUNC into another integer type
  CConvert (TElem e) (CExpr _ _ (CStandard "TRUNC" [a])) | isInt e -> do
    Ex x <- expr cx a
    Just (Ex (x >>= orFault pos . truncTo pol e))
  CConvert t a -> do
    Ex x <- expr cx a
    let !(Convert conversion) = convertOn pol (ceType a) t
    Just (Ex (x >>= orFault pos . conversion))
  -- NX-OP-87: TIME(), the clock in TIME's 32 bits
  CStandard f [] | f == timeFunction -> Just (Ex (VTime TIME . wrapUnder pol TIME . eClock <$> env))
  -- NX-OP-62, NX-OP-67: CODESYS evaluates only the selected input
  CStandard f _ | f `elem` ["MUX", "SEL"], pExtensions pol == ExtensionsCodesys -> Nothing
  CStandard f args -> do
    xs <- mapM (expr cx) args
    Just (Ex (mapM (\(Ex x) -> x) xs >>= orFault pos . standard pol f (map ceType args)))
  CCall f ins [] outs -> callFunction cx pos f ins outs
  CMethod d r ins [] outs -> callMethod cx pos d r ins outs
  -- NX-TYPE-75, NX-OP-68: ADR, the address of the variable's slot
  CAddressOf r -> do
    (sh, Ref pl) <- ref cx pos r
    when (size sh == 0) Nothing
    Just $ Ex $ do
      e <- env
      pl >>= \case
        Slot v o | MV.overlaps v (eStore e), Just a <- join (cAddresses cx V.!? o) -> pure $! VInt DWORD a
        _ -> abort Bail
  _ -> Nothing
  where
    pol = cPol cx
    pos = cePos ce

------------------------------------------------------------------------------
-- Small values on Int

-- | A value of an integer type of at most 32 bits, of BOOL or of TIME,
-- which the typed closures hold as an 'Int' (BOOL as 0 or 1, TIME as its
-- milliseconds) and box only where a value is stored or handed on. (An
-- integer's type comes with the number of its constructor, which a
-- value's is compared with.)
data Small = SmallInt !Elem {-# UNPACK #-} !Int | SmallBool | SmallTime
  deriving (Eq)

small :: Type -> Maybe Small
small t = case strip t of
  TElem BOOL -> Just SmallBool
  TElem TIME -> Just SmallTime
  TElem e | isInt e, intBits e <= 32 -> Just $! smallInt e
  _ -> Nothing

smallInt :: Elem -> Small
smallInt e = SmallInt e (fromEnum e)

-- | An expression whose value is small, computed on 'Int'.
data IEx = IEx !(forall s. M s Int)

boxed :: Small -> Int -> Value
boxed sm n = case sm of
  SmallInt e _ -> VInt e (toInteger n)
  SmallBool -> boolValue (n /= 0)
  SmallTime -> VTime TIME (toInteger n)
{-# INLINE boxed #-}

-- | The Int of a small value of the expected form; any other form (which
-- the checked program does not produce) leaves the cycle to the readable
-- evaluator.
unboxed :: Small -> Value -> M s Int
unboxed sm v = case (sm, v) of
  (SmallInt _ t, VInt e' (IS x)) | fromEnum e' == t -> pure (I# x)
  (SmallBool, VBool b) -> pure $! if b then 1 else 0
  (SmallTime, VTime TIME (IS x)) -> pure (I# x)
  _ -> abort Bail
{-# INLINE unboxed #-}

-- | The readable meaning of an operator on small operands, for the cases
-- the closures leave to it (a result outside the type, a zero divisor, an
-- operator without an Int case).
viaBinary :: Policies -> Pos -> BinOp -> Small -> Small -> Int -> Int -> M s Int
viaBinary pol p o sm rsm x y = orFault p (binary pol o (boxed sm x) (boxed sm y)) >>= unboxed rsm
{-# NOINLINE viaBinary #-}

-- | A small expression, as 'expr' computes it: each operator's Int case is
-- the one "Stref.IEC.Fast.Operators" takes ('binaryOn', 'convertOn',
-- checked there against the readable functions), the rest the readable
-- function's.
intExpr :: Cx -> Small -> CExpr -> Maybe IEx
intExpr cx sm ce = case ceNode ce of
  CConst v | Just n <- constant v -> Just (IEx (pure n))
  -- (a small value is elementary: a read that is no slot's is outside the slice)
  CRead r -> whereIs cx pos r >>= \case
    (Leaf, w) -> case w of
        -- the slot's value unboxed in the same closure
        Fixed b o -> Just $ IEx $ case sm of
          SmallInt _ t -> M $ \e -> atBase b e o MV.read >>= \case
            VInt e' (IS x) | fromEnum e' == t -> pure (I# x)
            _ -> unM (abort Bail) e
          SmallBool -> M $ \e -> atBase b e o MV.read >>= \case
            VBool x -> pure $! fromEnum x
            _ -> unM (abort Bail) e
          SmallTime -> M (\e -> atBase b e o MV.read) >>= unboxed SmallTime
        Computed b c (Offset off) -> Just (IEx (off >>= \o -> M (\e -> atBase b e (c + o) MV.read) >>= unboxed sm))
        Anywhere (Ref pl) -> Just (IEx (pl >>= readLeaf >>= unboxed sm))
    _ -> Nothing
  CBinary o a b
    | Just sa <- small (ceType a)
    , small (ceType b) == Just sa
    , Just Nothing <- divCheck o b -> do
        IEx x <- intExpr cx sa a
        IEx y <- intExpr cx sa b
        let slow = viaBinary pol pos o sa sm
            numeric e =
              let (lo, hi) = rangeUnder pol e
                  !lo' = fromInteger lo :: Int
                  !hi' = fromInteger hi :: Int
                  exact g = both x y (\u v -> let n = g u v in if lo' <= n && n <= hi' then pure n else slow u v)
                  {-# INLINE exact #-}
                  dividing g = both x y (\u v -> if v == 0 then slow u v else let n = g u v in if lo' <= n && n <= hi' then pure n else slow u v)
                  {-# INLINE dividing #-}
                  compared g = both x y (\u v -> pure $! fromEnum (g u v))
                  {-# INLINE compared #-}
               in case intCase pol o of
                    Exact g -> exact g
                    Dividing g -> dividing g
                    Compared g -> compared g
                    Bitwise g -> both x y (\u v -> pure $! g u v)
                    NoIntCase -> both x y slow
        case (sa, o) of
          _ | not (fits sa o) -> both x y slow
          -- TC-OP-6: short-circuit is a policy; TC-OP-5: the left operand first
          (SmallBool, BAnd) | pShortCircuit pol == ShortCircuit -> Just (IEx (x >>= \u -> if u == 0 then pure 0 else y))
          (SmallBool, BOr) | pShortCircuit pol == ShortCircuit -> Just (IEx (x >>= \u -> if u /= 0 then pure 1 else y))
          (SmallBool, BAnd) -> both x y (\u v -> pure $! u .&. v)
          (SmallBool, BOr) -> both x y (\u v -> pure $! u .|. v)
          (SmallBool, BXor) -> both x y (\u v -> pure $! u `xor` v)
          (SmallBool, BEq) -> both x y (\u v -> pure $! fromEnum (u == v))
          (SmallBool, BNe) -> both x y (\u v -> pure $! fromEnum (u /= v))
          -- TC-OP-49, TC-OP-52: durations add and subtract in TIME's
          -- range; they compare as their milliseconds
          (SmallTime, _)
            | o `elem` [BAdd, BSub, BLt, BGt, BLe, BGe, BEq, BNe] -> numeric TIME
            | otherwise -> both x y slow
          (SmallInt e _, _) -> numeric e
          _ -> both x y slow
  CUnary o a | Just sa <- small (ceType a) -> do
    IEx x <- intExpr cx sa a
    let slow u = orFault pos (unary pol o (boxed sa u)) >>= unboxed sm
    Just $ IEx $ case (sa, o) of
      _ | sm /= sa -> x >>= slow
      (SmallBool, UNot) -> (1 -) <$> x
      (SmallInt e _, UNeg) ->
        let (lo, hi) = rangeUnder pol e
            !lo' = fromInteger lo :: Int
            !hi' = fromInteger hi :: Int
         in x >>= \u -> let n = negate u in if lo' <= n && n <= hi' then pure n else slow u
      _ -> x >>= slow
  CConvert (TElem e) (CExpr _ _ (CStandard "TRUNC" [_])) | isInt e -> viaValue
  -- TC-CONV-16: a number to TIME is milliseconds, and back
  CConvert (TElem to) a | Just sa <- small (ceType a), sa /= SmallBool, sm /= SmallBool, small (TElem to) == Just sm -> do
    IEx x <- intExpr cx sa a
    let !(Convert conversion) = convertOn pol (ceType a) (TElem to)
        (lo, hi) = rangeUnder pol to
        !lo' = fromInteger lo :: Int
        !hi' = fromInteger hi :: Int
    -- an integer the target type's range holds is the same number
    Just (IEx (x >>= \u -> if lo' <= u && u <= hi' then pure u else orFault pos (conversion (boxed sa u)) >>= unboxed sm))
  _ -> viaValue
  where
    pol = cPol cx
    pos = cePos ce
    -- the result's form: an operator's operands' or BOOL
    fits sa o
      | o `elem` [BLt, BGt, BLe, BGe, BEq, BNe] = sm == SmallBool
      | otherwise = sm == sa
    constant v = case (sm, v) of
      (SmallInt e _, VInt e' (IS x)) | e == e' -> Just (I# x)
      (SmallBool, VBool b) -> Just (fromEnum b)
      (SmallTime, VTime TIME (IS x)) -> Just (I# x)
      _ -> Nothing
    viaValue = do
      Ex v <- exprValue cx ce
      Just (IEx (v >>= unboxed sm))
    both :: (forall s. M s Int) -> (forall s. M s Int) -> (forall s. Int -> Int -> M s Int) -> Maybe IEx
    both x y f = Just (IEx (x >>= \u -> y >>= \v -> f u v))
    {-# INLINE both #-}
    -- NX-ERR-11..13: a division under CheckDiv* stays on values
    divCheck o b = case (o, baseElem (ceType b) >>= checkDivName) of
      (BDiv, Just name) -> implicit cx pos name
      _ -> Just Nothing

-- | A condition (IF, WHILE, REPEAT).
data Cond = Cond !(forall s. M s Bool)

condition :: Cx -> CExpr -> Maybe Cond
condition cx ce = case small (ceType ce) of
  Just SmallBool -> do
    IEx i <- intExpr cx SmallBool ce
    Just (Cond ((/= 0) <$> i))
  _ -> do
    Ex v <- expr cx ce
    Just (Cond (asBool <$> v))
