-- | Running a real engine installed by the user, through its adapter
-- (docs/engines.md): find its tools, run them in a scratch directory,
-- answer the stref-engine/1 request. The meaning of each step is in the
-- adapter's pure module ("Stref.Engines.Matiec", "Stref.Engines.Ironplc");
-- here are only files and processes.
module Stref.Engines.Run
  ( Engine (..)
  , engines
  , engineByName
  , Tools
  , findTools
  , toolsText
  , engineVersion
  , answerWith
  ) where

import Control.Exception (SomeException, bracket, try)
import Data.List (isSuffixOf, sort)
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Text.IO as TIO
import Stref.Conformance.Protocol
import Stref.Engine (requestPolicies)
import qualified Stref.Engines.Ironplc as Ironplc
import qualified Stref.Engines.Matiec as Matiec
import qualified Stref.Engines.Rusty as Rusty
import Stref.Policy (Model (..), Policies (..))
import System.Directory
import System.Environment (lookupEnv)
import System.Exit (ExitCode (..))
import System.FilePath ((</>))
import System.IO (hClose, hPutStrLn, openTempFile, stderr)
import System.Process (proc, readCreateProcessWithExitCode, readProcessWithExitCode)
import System.Timeout (timeout)

-- | An engine stref has an adapter for.
data Engine = Engine
  { engName :: Text -- ^ as given to @--engine@
  , engTitle :: Text
  , engVariable :: String -- ^ the environment variable that locates it
  , engOnPath :: Maybe String -- ^ the program looked for on PATH when the variable is not set
  , engAdapter :: Adapter
  }

-- | Which adapter drives it.
data Adapter = MatiecAdapter | IronplcAdapter | RustyAdapter

engines :: [Engine]
engines =
  [ Engine "matiec" "MATIEC (iec2c of Beremiz)" "STREF_MATIEC" (Just "iec2c") MatiecAdapter
  , Engine "openplc" "OpenPLC's fork of MATIEC" "STREF_OPENPLC" Nothing MatiecAdapter
  , Engine "ironplc" "IronPLC (ironplcc and ironplcvm)" "STREF_IRONPLC" (Just "ironplcc") IronplcAdapter
  , Engine "rusty" "RuSTy (plc and its iec61131std library)" "STREF_RUSTY" (Just "plc") RustyAdapter
  ]

engineByName :: Text -> Maybe Engine
engineByName n = case filter ((== T.toLower n) . engName) engines of
  e : _ -> Just e
  [] -> Nothing

-- | Where an engine's tools are.
data Tools = MatiecTools Matiec | IronplcTools Ironplc | RustyTools Rusty

data Matiec = Matiec
  { tCompiler :: FilePath -- ^ iec2c
  , tLibrary :: FilePath -- ^ its lib directory (the ST declarations, and lib/C)
  , tCc :: FilePath -- ^ the C compiler
  , tSeconds :: Int -- ^ time limit of one run of the compiled program
  }

data Ironplc = Ironplc
  { iCompiler :: FilePath -- ^ ironplcc
  , iVm :: FilePath -- ^ ironplcvm
  }

data Rusty = Rusty
  { rPlc :: FilePath -- ^ plc
  , rLib :: FilePath -- ^ the directory of libiec61131std.so
  , rInclude :: FilePath -- ^ the directory of the library's ST declarations
  , rCc :: FilePath -- ^ the C compiler that links the driver
  }

-- | The tools found, as @stref adapter --check@ shows them.
toolsText :: Tools -> Text
toolsText = \case
  MatiecTools m -> T.pack (tCompiler m)
  IronplcTools i -> T.pack (iCompiler i) <> ", " <> T.pack (iVm i)
  RustyTools r -> T.pack (rPlc r) <> ", " <> T.pack (rLib r) <> ", " <> T.pack (rInclude r)

-- | The engine's tools, or why it is not there. The variable names the
-- directory that holds the tools (or the compiler itself); without it, the
-- compiler on PATH.
findTools :: Engine -> IO (Either Text Tools)
findTools e = do
  var <- lookupEnv (engVariable e)
  compiler <- case var of
    Just v | not (null v) -> do
      isDir <- doesDirectoryExist v
      pure (Just (if isDir then v </> compilerName else v))
    _ -> maybe (pure Nothing) findExecutable (engOnPath e)
  case compiler of
    Nothing -> pure (Left (engTitle e <> " is not installed: set " <> T.pack (engVariable e) <> " to the directory that holds " <> T.pack compilerName <> extra <> maybe "" (\p -> ", or put " <> T.pack p <> " on PATH") (engOnPath e)))
    Just c -> do
      exists <- doesFileExist c
      if not exists
        then pure (Left (T.pack c <> " does not exist (" <> T.pack (engVariable e) <> ")"))
        else case engAdapter e of
          MatiecAdapter -> matiecTools c
          IronplcAdapter -> ironplcTools c
          RustyAdapter -> rustyTools c
  where
    (compilerName, extra) = case engAdapter e of
      MatiecAdapter -> ("iec2c", " and its lib/")
      IronplcAdapter -> ("ironplcc", " and ironplcvm")
      -- RuSTy's installation is a tree: bin/plc beside lib/ and include/
      RustyAdapter -> ("bin/plc", ", lib/libiec61131std.so and include/*.st")

-- | iec2c with the @lib@ beside it; @STREF_MATIEC_LIB@ overrides the
-- library, @STREF_CC@ the C compiler (default @cc@).
matiecTools :: FilePath -> IO (Either Text Tools)
matiecTools c = do
  libVar <- lookupEnv "STREF_MATIEC_LIB"
  let lib = maybe (takeDir c </> "lib") id libVar
  libOk <- doesFileExist (lib </> "ieclib.txt")
  ccVar <- lookupEnv "STREF_CC"
  cc <- maybe (maybe "cc" id <$> findExecutable "cc") pure ccVar
  pure $
    if not libOk
      then Left ("no ieclib.txt in " <> T.pack lib <> ": set STREF_MATIEC_LIB to iec2c's lib directory")
      else Right (MatiecTools (Matiec c lib cc 10))

-- | ironplcc with ironplcvm beside it, or on PATH.
ironplcTools :: FilePath -> IO (Either Text Tools)
ironplcTools c = do
  let beside = takeDir c </> "ironplcvm"
  here <- doesFileExist beside
  vm <- if here then pure (Just beside) else findExecutable "ironplcvm"
  pure $ case vm of
    Just v -> Right (IronplcTools (Ironplc c v))
    Nothing -> Left ("no ironplcvm beside " <> T.pack c <> " nor on PATH: IronPLC's VM runs the compiled programs")

-- | plc in a tree with lib/libiec61131std.so and include/ (the library's
-- ST declarations) beside its bin/; @STREF_CC@ the C compiler.
rustyTools :: FilePath -> IO (Either Text Tools)
rustyTools c = do
  let root = takeDir (takeDir c)
      lib = root </> "lib"
      include = root </> "include"
  libOk <- doesFileExist (lib </> "libiec61131std.so")
  incOk <- doesDirectoryExist include
  ccVar <- lookupEnv "STREF_CC"
  cc <- maybe (maybe "cc" id <$> findExecutable "cc") pure ccVar
  pure $
    if not libOk || not incOk
      then Left ("no lib/libiec61131std.so and include/ beside " <> T.pack c <> "'s bin/: RuSTy's standard library is part of its installation")
      else Right (RustyTools (Rusty c lib include cc))

takeDir :: FilePath -> FilePath
takeDir p = case reverse (dropWhile (/= '/') (reverse (dropTrailing p))) of
  "" -> "."
  d -> dropTrailing d
  where
    dropTrailing q = if length q > 1 && last q == '/' then init q else q

-- | What the engine's compiler says of its version.
engineVersion :: Tools -> IO Text
engineVersion t = do
  let (exe, args) = case t of
        MatiecTools m -> (tCompiler m, ["-v"])
        IronplcTools i -> (iCompiler i, ["version"])
        RustyTools r -> (rPlc r, ["--version"])
  r <- try (readProcessWithExitCode exe args "")
  pure $ case r of
    Left (_ :: SomeException) -> "version unknown"
    Right (_, out, err) -> case filter (not . T.null) (map T.strip (T.lines (T.pack (out <> err)))) of
      l : _ -> l
      [] -> "version unknown"

-- | The engine's answer to a request; Left: the adapter failed (the runner
-- records @engine-error@).
answerWith :: Tools -> Request -> IO (Either Text Answer)
answerWith tools rq = case requestPolicies [] rq of
  Left why -> pure (Right (AnswerUnsupported why))
  Right pol
    | pModel pol /= IecController -> pure (Right (AnswerUnsupported "the engine runs the IEC 61131-3 model, not the MasterTool XE controller"))
    | otherwise -> case tools of
        MatiecTools m -> matiecAnswer m pol rq
        IronplcTools i -> ironplcAnswer i pol rq
        RustyTools r -> rustyAnswer r pol rq

-- | Messages name files by their place in the scratch directory and the
-- engine's library, and the user's home as ~ (a panic of an engine built
-- with cargo names its registry there), not by this machine's paths.
scrubbing :: [(FilePath, Text)] -> IO (Either Text Answer) -> IO (Either Text Answer)
scrubbing places answer = do
  home <- either (const "") id <$> (try getHomeDirectory :: IO (Either SomeException FilePath))
  fmap (scrubAnswer (places ++ [(home, "~") | length home > 1])) <$> answer

-- | The places are replaced in order.
scrubAnswer :: [(FilePath, Text)] -> Answer -> Answer
scrubAnswer places = \case
  AnswerRejected l k m -> AnswerRejected l k (scrub m)
  AnswerUnsupported m -> AnswerUnsupported (scrub m)
  a -> a
  where
    scrub m = T.take 600 (foldl (\acc (p, r) -> T.replace (T.pack p) r acc) m places)

------------------------------------------------------------------------------
-- MATIEC

matiecAnswer :: Matiec -> Policies -> Request -> IO (Either Text Answer)
matiecAnswer tools pol rq = case Matiec.plan pol rq of
  Left why -> pure (Right (AnswerUnsupported why))
  Right pl -> withScratch (\dir -> scrubbing [(tLibrary tools, "<lib>"), (dir, "<scratch>")] (run pl dir))
  where
    run pl dir = do
      let source = dir </> T.unpack Matiec.caseFile
      TIO.writeFile source (Matiec.planSource pl)
      compiled <- timeout (compileSeconds * 1000000) (readCreateProcessWithExitCode (proc (tCompiler tools) ["-p", "-I", tLibrary tools, "-T", dir, source]) "")
      case compiled of
        Nothing -> pure (Right (AnswerRejected Nothing Nothing ("iec2c ran for more than " <> T.pack (show compileSeconds) <> " s on this program without finishing")))
        Just result -> compiledWith pl dir result
    compiledWith pl dir (rc, _, err) =
      case rc of
        ExitFailure n -> do
          writeFile (dir </> "iec2c.err") err
          pure (Right (Matiec.compileAnswer n (T.pack err)))
        ExitSuccess -> do
          let header = dir </> "LOCATED_VARIABLES.h"
          hasHeader <- doesFileExist header
          located <- if hasHeader then Matiec.locatedNames <$> TIO.readFile header else pure []
          case Matiec.driverSource pl located of
            Left why -> pure (Right (AnswerUnsupported why))
            Right driver -> do
              TIO.writeFile (dir </> "stref_driver.c") driver
              files <- sort . filter (\f -> ".c" `isSuffixOf` f && f `notElem` ["POUS.c", "stref_driver.c"]) <$> listDirectory dir
              let include = ["-w", "-O0", "-fwrapv", "-I", tLibrary tools </> "C", "-I", dir]
                  objects = [dir </> (take (length f - 2) f <> ".o") | f <- files]
              -- iec2c's C first: where it does not compile, the engine's
              -- tool chain rejects the program
              generated <- mapM (\(f, o) -> readCreateProcessWithExitCode (proc (tCc tools) (include ++ ["-c", dir </> f, "-o", o])) "") (zip files objects)
              case [e | (ExitFailure _, _, e) <- generated] of
                e : _ -> pure (Right (AnswerRejected Nothing Nothing ("the C code iec2c generated does not compile: " <> T.pack e)))
                [] -> do
                  (ccRc, _, ccErr) <- readCreateProcessWithExitCode (proc (tCc tools) (include ++ ["-c", dir </> "stref_driver.c", "-o", dir </> "stref_driver.o"])) ""
                  (ldRc, _, ldErr) <- readCreateProcessWithExitCode (proc (tCc tools) (["-o", dir </> "program", dir </> "stref_driver.o"] ++ objects ++ ["-lm"])) ""
                  case (ccRc, ldRc) of
                    (ExitFailure _, _) -> pure (Left ("the driver did not compile: " <> T.pack (take 2000 ccErr)))
                    -- a function the generated code calls that the engine's
                    -- library lacks: its tool chain rejects the program
                    (_, ExitFailure _) -> pure (Right (AnswerRejected Nothing Nothing ("the C code iec2c generated does not link: " <> linkErrors ldErr)))
                    _ -> do
                      out <- timeout (tSeconds tools * 1000000) (readCreateProcessWithExitCode (proc (dir </> "program") []) "")
                      mapM_ (\(_, o, _) -> writeFile (dir </> "program.out") o) out
                      pure . Right . Matiec.runAnswer pl $ case out of
                        Nothing -> Matiec.TimedOut
                        Just (_, o, _) -> Matiec.Finished (T.pack o)

------------------------------------------------------------------------------
-- IronPLC

ironplcAnswer :: Ironplc -> Policies -> Request -> IO (Either Text Answer)
ironplcAnswer tools pol rq = withScratch $ \dir -> do
  let pl = Ironplc.plan pol rq
      source = dir </> T.unpack Ironplc.caseFile
      bytecode = dir </> "case.iplc"
  TIO.writeFile source (Ironplc.planSource pl)
  compiled <- timeout (compileSeconds * 1000000) (readCreateProcessWithExitCode (proc (iCompiler tools) (["compile"] ++ Ironplc.planFlags pl ++ [source, "-o", bytecode])) "")
  scrubbing [(dir, "<scratch>")] $ case compiled of
    Nothing -> pure (Right (AnswerRejected Nothing Nothing ("ironplcc ran for more than " <> T.pack (show compileSeconds) <> " s on this program without finishing")))
    Just (ExitFailure n, _, err) -> do
      writeFile (dir </> "ironplcc.err") err
      pure (Right (Ironplc.compileAnswer n (T.pack err)))
    Just (ExitSuccess, _, _) -> case Ironplc.planRun pl of
      Left why -> pure (Right (AnswerUnsupported why))
      Right r -> do
        out <- timeout (Ironplc.runSeconds r * 1000000) (readCreateProcessWithExitCode (proc (iVm tools) ["run", bytecode, "--scans", show (Ironplc.runScans r), "--dump-vars"]) "")
        mapM_ (\(_, o, e) -> writeFile (dir </> "vm.out") o >> writeFile (dir </> "vm.err") e) out
        pure . Ironplc.runAnswer pl $ case out of
          Nothing -> Ironplc.TimedOut
          Just (rc, o, e) -> Ironplc.Finished (case rc of ExitSuccess -> 0; ExitFailure n -> n) (T.pack o) (T.pack e)

------------------------------------------------------------------------------
-- RuSTy

rustyAnswer :: Rusty -> Policies -> Request -> IO (Either Text Answer)
rustyAnswer tools pol rq = case Rusty.plan pol rq of
  Left why -> pure (Right (AnswerUnsupported why))
  Right pl -> withScratch $ \dir -> do
    let source = dir </> T.unpack Rusty.caseFile
        probes = dir </> T.unpack Rusty.probeFile
        object = dir </> "case.o"
        withProbes = not (T.null (Rusty.planProbes pl))
    TIO.writeFile source (Rusty.planSource pl)
    TIO.writeFile probes (Rusty.planProbes pl)
    let args = ["-c", source] ++ [probes | withProbes] ++ ["-i", rInclude tools </> "*.st", "-o", object, "--error-format", "clang"]
    compiled <- timeout (compileSeconds * 1000000) (readCreateProcessWithExitCode (proc (rPlc tools) args) "")
    scrubbing [(rInclude tools, "<include>"), (dir, "<scratch>")] $ case compiled of
      Nothing -> pure (Right (AnswerRejected Nothing Nothing ("plc ran for more than " <> T.pack (show compileSeconds) <> " s on this program without finishing")))
      Just (ExitFailure n, _, err) -> do
        writeFile (dir </> "plc.err") err
        case Rusty.compileAnswer n (T.pack err) of
          -- an error plc does not place: if the case compiles without the
          -- probes, the driver's access to a variable is what failed
          AnswerRejected Nothing _ m | withProbes -> do
            alone <- timeout (compileSeconds * 1000000) (readCreateProcessWithExitCode (proc (rPlc tools) (["-c", source, "-i", rInclude tools </> "*.st", "-o", object, "--error-format", "clang"])) "")
            pure . Right $ case alone of
              Just (ExitSuccess, _, _) -> AnswerUnsupported ("plc compiles the case but not the driver's access to the variables it observes: " <> m)
              _ -> AnswerRejected Nothing Nothing m
          a -> pure (Right a)
      Just (ExitSuccess, _, _) -> case Rusty.planRun pl of
        Left why -> pure (Right (AnswerUnsupported why))
        Right r -> do
          TIO.writeFile (dir </> "stref_driver.c") (Rusty.driverSource r)
          let program = dir </> "program"
          (ldRc, _, ldErr) <- readCreateProcessWithExitCode (proc (rCc tools) ["-w", "-no-pie", "-O0", dir </> "stref_driver.c", object, "-L", rLib tools, "-liec61131std", "-Wl,-rpath," <> rLib tools, "-lm", "-o", program]) ""
          case ldRc of
            -- a POU named like a C library function, or one plc left undefined
            ExitFailure _ -> pure (Right (AnswerRejected Nothing Nothing ("the object plc compiled does not link with the driver: " <> linkErrors ldErr)))
            ExitSuccess -> do
              out <- timeout (10 * 1000000) (readCreateProcessWithExitCode (proc program []) "")
              mapM_ (\(_, o, _) -> writeFile (dir </> "program.out") o) out
              pure . Right . Rusty.runAnswer r $ case out of
                Nothing -> Rusty.TimedOut
                Just (_, o, _) -> Rusty.Finished (T.pack o)

-- | How long a compiler may take on one program (iec2c can loop on some input).
compileSeconds :: Int
compileSeconds = 20

-- | The linker's errors, without its warnings.
linkErrors :: String -> Text
linkErrors out = (T.intercalate "; " [T.strip l | l <- T.lines (T.pack out), any (`T.isInfixOf` l) ["undefined reference", "error"]])

-- | A scratch directory, removed afterwards unless @STREF_ADAPTER_KEEP@ is
-- set (then its path is written to standard error, to look at what the
-- engine was given and what it printed).
withScratch :: (FilePath -> IO (Either Text a)) -> IO (Either Text a)
withScratch act = do
  tmp <- getTemporaryDirectory
  keep <- lookupEnv "STREF_ADAPTER_KEEP"
  let done path = case keep of
        Just _ -> hPutStrLn stderr ("stref adapter: kept " <> path)
        Nothing -> removePathForcibly path
  r <- try $ bracket (mkScratch tmp) done act
  pure $ case r of
    Left (e :: SomeException) -> Left ("the adapter failed: " <> T.pack (show e))
    Right x -> x
  where
    mkScratch tmp = do
      (path, h) <- openTempFile tmp "stref-engine"
      hClose h
      removeFile path
      createDirectory path
      pure path
